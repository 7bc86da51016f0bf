"""Independent references for the Taylor target's pre-write checks (no recurrences of `series` here).

`lie_coefficients`: the Taylor coefficients y_k = L_f^k y / k! of the solution through (t, y) (L_f the
Lie derivative along the flow, so y_k = y^(k)(t) / k!), from the model's rhs as the numba target
prints it (`plain_python.python_source`, the kernel the lowering checks compare with the dense symbolic
solve), evaluated on truncated power series in s: `Series` composes the elementary functions with
their Maclaurin series (sin(a + q) = sin a cos q + cos a sin q with cos q = sum (-1)^k q^2k / (2k)!,
1/(b + q) = sum (-q)^k / b^(k+1), ...), Taylor's theorem as such, not the automatic-differentiation
recurrences, in `DIGITS`-digit arithmetic (mpmath).  Then y_{k+1} = [s^k] f(t + s, y(s)) / (k + 1),
order by order.

`odefun_step`: the solution after one step by mpmath's own Taylor ODE solver (`mpmath.odefun`) on the
same printed rhs at 30 digits.
"""

from __future__ import annotations

from types import SimpleNamespace

import mpmath
import numpy as np

from ...plain_python import python_source
from ...emit import tables

DIGITS = 60


class Series:
    """A power series in s truncated after s^K, coefficients mpf (at the working precision)."""

    __slots__ = ("c",)
    K = 0  # set by `_context`

    def __init__(self, c):
        self.c = list(c)[: Series.K + 1] + [mpmath.mpf(0)] * (Series.K + 1 - len(c))

    @staticmethod
    def lift(x) -> "Series":
        return x if isinstance(x, Series) else Series([mpmath.mpf(x)])

    # arithmetic
    def __add__(self, o):
        o = Series.lift(o)
        return Series([a + b for a, b in zip(self.c, o.c)])

    __radd__ = __add__

    def __neg__(self):
        return Series([-a for a in self.c])

    def __pos__(self):
        return self

    def __sub__(self, o):
        return self + (-Series.lift(o))

    def __rsub__(self, o):
        return Series.lift(o) - self

    def __mul__(self, o):
        if not isinstance(o, Series):
            o = mpmath.mpf(o)
            return Series([a * o for a in self.c])
        K = Series.K
        out = [mpmath.mpf(0)] * (K + 1)
        for i, a in enumerate(self.c):
            if a:
                for j in range(K + 1 - i):
                    out[i + j] += a * o.c[j]
        return Series(out)

    __rmul__ = __mul__

    def reciprocal(self) -> "Series":
        """1 / (b + q) = sum_k (-q)^k / b^(k+1), q(0) = 0."""
        b = self.c[0]
        q = Series([0] + self.c[1:])
        return _power_sum(-q * (1 / b), [1 / b] * (Series.K + 1))

    def __truediv__(self, o):
        if not isinstance(o, Series):
            return self * (1 / mpmath.mpf(o))
        return self * o.reciprocal()

    def __rtruediv__(self, o):
        return Series.lift(o) * self.reciprocal()

    def __pow__(self, e):
        e = float(e) if not isinstance(e, mpmath.mpf) else e
        if float(e) == int(e) and abs(int(e)) <= 1000:
            n = int(e)
            out = Series([1])
            base = self if n >= 0 else self.reciprocal()
            for _ in range(abs(n)):
                out = out * base
            return out
        b = self.c[0]
        q = Series([0] + self.c[1:]) * (1 / b)
        coeffs = [b ** e * mpmath.binomial(e, k) for k in range(Series.K + 1)]  # b^e (1 + q/b)^e
        return _power_sum(q, coeffs)

    # comparisons decide branches (a Piecewise of the time) by the value at s = 0
    def __lt__(self, o):
        return self.c[0] < Series.lift(o).c[0]

    def __gt__(self, o):
        return self.c[0] > Series.lift(o).c[0]

    def __le__(self, o):
        return self.c[0] <= Series.lift(o).c[0]

    def __ge__(self, o):
        return self.c[0] >= Series.lift(o).c[0]


def _power_sum(q: Series, coeffs) -> Series:
    """sum_k coeffs[k] q^k (q(0) = 0, so q^k starts at s^k and the sum ends at K)."""
    out = Series([coeffs[0]])
    qk = Series([1])
    for k in range(1, Series.K + 1):
        qk = qk * q
        out = out + qk * coeffs[k]
    return out


def _split(x: Series):
    return x.c[0], Series([0] + x.c[1:])


def _sin_cos(x):
    if not isinstance(x, Series):
        return mpmath.sin(x), mpmath.cos(x)
    a, q = _split(x)
    K = Series.K
    fact = [mpmath.factorial(k) for k in range(K + 1)]
    cq = _power_sum(q, [(-1) ** (k // 2) / fact[k] if k % 2 == 0 else 0 for k in range(K + 1)])
    sq = _power_sum(q, [(-1) ** (k // 2) / fact[k] if k % 2 == 1 else 0 for k in range(K + 1)])
    return sq * mpmath.cos(a) + cq * mpmath.sin(a), cq * mpmath.cos(a) - sq * mpmath.sin(a)


def _exp(x):
    if not isinstance(x, Series):
        return mpmath.exp(x)
    a, q = _split(x)
    return _power_sum(q, [1 / mpmath.factorial(k) for k in range(Series.K + 1)]) * mpmath.exp(a)


def _log(x):
    if not isinstance(x, Series):
        return mpmath.log(x)
    a, q = _split(x)
    return _power_sum(q * (1 / a), [0] + [mpmath.mpf((-1) ** (k + 1)) / k for k in range(1, Series.K + 1)]) \
        + mpmath.log(a)


def _atan(x):
    """atan(a + q) = atan a + atan(q / (1 + a (a + q))) (the addition formula), then the Maclaurin series."""
    if not isinstance(x, Series):
        return mpmath.atan(x)
    a, q = _split(x)
    z = q / (x * a + 1)
    return _power_sum(z, [mpmath.mpf((-1) ** (k // 2)) / k if k % 2 else 0 for k in range(Series.K + 1)]) \
        + mpmath.atan(a)


def _sqrt(x):
    return x ** mpmath.mpf("0.5") if isinstance(x, Series) else mpmath.sqrt(x)


def _namespace() -> SimpleNamespace:
    return SimpleNamespace(sin=lambda x: _sin_cos(x)[0], cos=lambda x: _sin_cos(x)[1], exp=_exp, log=_log,
                           atan=_atan, sqrt=_sqrt, pi=mpmath.pi, tan=None)


def _rhs_function(ir):
    """The printed rhs as f(t, y, p) -> list, on whatever numbers (Series, mpf) it is given."""
    scope = {"math": _namespace(), "np": SimpleNamespace(empty=lambda n: [None] * int(n))}
    if ir.loops is not None:
        scope.update({name: np.array(values, dtype=np.int64 if kind == "int" else float)
                      for name, kind, values in tables(ir.loops.split)})
    exec(compile(python_source(ir, "rhs"), f"<{ir.name}.rhs (series reference)>", "exec"), scope)  # noqa: S102
    inner = scope["_f"]
    n = ir.n_states

    def f(t, y, p):
        return inner(t, list(y), list(p), [None] * n)
    return f


def lie_coefficients(ir, t: float, y, p, order: int, digits: int = DIGITS) -> np.ndarray:
    """y_0..y_order (rows) of the solution through (t, y) at parameters p, in `digits`-digit arithmetic,
    rounded to double at the end."""
    f = _rhs_function(ir)
    with mpmath.workdps(digits):
        p_ = [mpmath.mpf(float(v)) for v in p]
        rows = [[mpmath.mpf(float(v)) for v in y]]
        for K in range(order):
            Series.K = K
            ys = [Series([rows[k][i] for k in range(K + 1)]) for i in range(len(y))]
            ts = Series([mpmath.mpf(float(t)), 1])
            fs = f(ts, ys, p_)
            rows.append([Series.lift(v).c[K] / (K + 1) for v in fs])
        return np.array([[float(v) for v in row] for row in rows])


def odefun_step(ir, t: float, y, p, h: float, digits: int = 30) -> list:
    """The state at t + h (mpf) by mpmath.odefun (its Taylor method, `digits` digits) on the printed rhs."""
    f = _rhs_function(ir)
    with mpmath.workdps(digits):
        p_ = [mpmath.mpf(float(v)) for v in p]
        sol = mpmath.odefun(lambda x, z: f(x, z, p_), mpmath.mpf(float(t)), [mpmath.mpf(float(v)) for v in y],
                            degree=20)  # (its default degree takes twice as long here)
        return list(sol(mpmath.mpf(float(t)) + mpmath.mpf(float(h))))


__all__ = ["DIGITS", "Series", "lie_coefficients", "odefun_step"]
