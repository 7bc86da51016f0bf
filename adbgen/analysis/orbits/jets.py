"""Exact directional derivatives of a generated model by truncated Taylor series (a "jet").

    J0, J1, J2 = jacobian_jet(model, t, y, p, q, order=2)

J(y + s q) = J0 + s J1 + s^2 J2 + O(s^3) with J the model's generated Jacobian, so that

    J1 v = B(q, v)            (the second derivative of the rhs: D^2 f(y)[q, v])
    2 J2 v = C(q, q, v)       (the third: D^3 f(y)[q, q, v])

exactly (to rounding): the generated Jacobian's own statements (its numba function's Python source,
`jac_inplace.py_func`) are evaluated with every variable a truncated power series in s, propagated
statement by statement by the automatic-differentiation recurrences of sums, products, quotients,
powers and the sin/cos pair, as a Taylor-series integrator does.  The direction q may be complex (the
series coefficients then are the complex multilinear forms), which is what the first Lyapunov
coefficient needs: B(q, q-bar), B(q, q), C(q, q, q-bar) from one evaluation.

This is the stand-in until the Taylor target emits a compiled jet kernel (issue 22): same recurrences,
interpreted here.  The independent check is `differences`: central differences of the exact Jacobian.
"""

from __future__ import annotations

import math
import types

import numpy as np

from ..loading import AnalysisError, Model


class Jet:
    """A truncated power series sum_k c_k s^k, k <= order (coefficients real or complex)."""

    __slots__ = ("c",)
    __array_priority__ = 1000

    def __init__(self, c):
        self.c = c

    @staticmethod
    def const(v, n):
        c = np.zeros(n, dtype=complex if isinstance(v, complex) else float)
        c[0] = v
        return c

    def _other(self, o):
        if isinstance(o, Jet):
            return o.c
        if isinstance(o, (int, float, complex, np.number)):
            c = np.zeros(len(self.c), dtype=np.result_type(self.c, type(o)))
            c[0] = o
            return c
        return NotImplemented

    def __add__(self, o):
        oc = self._other(o)
        return NotImplemented if oc is NotImplemented else Jet(self.c + oc)

    __radd__ = __add__

    def __sub__(self, o):
        oc = self._other(o)
        return NotImplemented if oc is NotImplemented else Jet(self.c - oc)

    def __rsub__(self, o):
        oc = self._other(o)
        return NotImplemented if oc is NotImplemented else Jet(oc - self.c)

    def __neg__(self):
        return Jet(-self.c)

    def __pos__(self):
        return self

    def __mul__(self, o):
        if isinstance(o, Jet):
            return Jet(np.convolve(self.c, o.c)[: len(self.c)])
        if isinstance(o, (int, float, complex, np.number)):
            return Jet(self.c * o)
        return NotImplemented

    __rmul__ = __mul__

    def __truediv__(self, o):
        if isinstance(o, (int, float, complex, np.number)):
            return Jet(self.c / o)
        if not isinstance(o, Jet):
            return NotImplemented
        return Jet(_divide(self.c, o.c))

    def __rtruediv__(self, o):
        oc = self._other(o)
        return NotImplemented if oc is NotImplemented else Jet(_divide(oc, self.c))

    def __pow__(self, e):
        if isinstance(e, Jet):
            return exp(log(self) * e)
        if float(e) == int(e) and abs(e) <= 64:
            n = int(e)
            out = Jet(Jet.const(1.0, len(self.c)).astype(self.c.dtype))
            base = self if n >= 0 else 1.0 / self
            for _ in range(abs(n)):
                out = out * base
            return out
        return Jet(_power(self.c, float(e)))

    def __rpow__(self, b):
        return exp(log(b) * self) if not isinstance(b, Jet) else b ** self

    # comparisons (branches of the generated code) by the value
    def __lt__(self, o):
        return self.c[0].real < (o.c[0].real if isinstance(o, Jet) else o)

    def __le__(self, o):
        return self.c[0].real <= (o.c[0].real if isinstance(o, Jet) else o)

    def __gt__(self, o):
        return self.c[0].real > (o.c[0].real if isinstance(o, Jet) else o)

    def __ge__(self, o):
        return self.c[0].real >= (o.c[0].real if isinstance(o, Jet) else o)

    def __float__(self):
        return float(self.c[0].real)


def _divide(a, b):
    n = len(a)
    c = np.zeros(n, dtype=np.result_type(a, b))
    for k in range(n):
        c[k] = (a[k] - np.dot(b[1:k + 1], c[k - 1::-1][:k])) / b[0] if k else a[0] / b[0]
    return c


def _power(a, e):
    n = len(a)
    r = np.zeros(n, dtype=np.result_type(a, float))
    r[0] = a[0] ** e
    for k in range(1, n):
        j = np.arange(1, k + 1)
        r[k] = np.sum(((e + 1) * j - k) * a[j] * r[k - j]) / (k * a[0])
    return r


def sin_cos(a: Jet):
    n = len(a.c)
    s = np.zeros(n, dtype=a.c.dtype)
    c = np.zeros(n, dtype=a.c.dtype)
    s[0], c[0] = np.sin(a.c[0]), np.cos(a.c[0])
    for k in range(1, n):
        j = np.arange(1, k + 1)
        s[k] = np.sum(j * a.c[j] * c[k - j]) / k
        c[k] = -np.sum(j * a.c[j] * s[k - j]) / k
    return Jet(s), Jet(c)


def exp(a):
    if not isinstance(a, Jet):
        return math.exp(a)
    n = len(a.c)
    e = np.zeros(n, dtype=a.c.dtype)
    e[0] = np.exp(a.c[0])
    for k in range(1, n):
        j = np.arange(1, k + 1)
        e[k] = np.sum(j * a.c[j] * e[k - j]) / k
    return Jet(e)


def log(a):
    if not isinstance(a, Jet):
        return math.log(a)
    n = len(a.c)
    out = np.zeros(n, dtype=a.c.dtype)
    out[0] = np.log(a.c[0])
    for k in range(1, n):
        j = np.arange(1, k)
        out[k] = (a.c[k] - np.sum(j * out[j] * a.c[k - j]) / k) / a.c[0]
    return Jet(out)


def _integrate(value0, derivative: Jet) -> Jet:
    n = len(derivative.c)
    c = np.zeros(n, dtype=derivative.c.dtype)
    c[0] = value0
    c[1:] = derivative.c[:-1] / np.arange(1, n)
    return Jet(c)


def _derivative(a: Jet) -> Jet:
    n = len(a.c)
    d = np.zeros(n, dtype=a.c.dtype)
    d[:-1] = a.c[1:] * np.arange(1, n)
    return Jet(d)


class _JetMath(types.SimpleNamespace):
    """What the generated code calls as `math.*`, for numbers and jets alike."""

    pi = math.pi
    e = math.e

    @staticmethod
    def sin(a):
        return sin_cos(a)[0] if isinstance(a, Jet) else math.sin(a)

    @staticmethod
    def cos(a):
        return sin_cos(a)[1] if isinstance(a, Jet) else math.cos(a)

    @staticmethod
    def tan(a):
        if not isinstance(a, Jet):
            return math.tan(a)
        s, c = sin_cos(a)
        return s / c

    @staticmethod
    def sqrt(a):
        return Jet(_power(a.c, 0.5)) if isinstance(a, Jet) else math.sqrt(a)

    @staticmethod
    def exp(a):
        return exp(a)

    @staticmethod
    def log(a):
        return log(a)

    @staticmethod
    def atan(a):
        if not isinstance(a, Jet):
            return math.atan(a)
        return _integrate(np.arctan(a.c[0]), _derivative(a) / (1.0 + a * a))

    @staticmethod
    def fabs(a):
        return (a if a.c[0].real >= 0 else -a) if isinstance(a, Jet) else math.fabs(a)


def _interpreted(fn):
    """The numba function's Python source with `math` and the scratch arrays able to hold jets."""
    py = getattr(fn, "py_func", fn)
    g = dict(py.__globals__)
    g["math"] = _JetMath()
    g["_scratch"] = lambda size: np.zeros(size, dtype=object)
    return types.FunctionType(py.__code__, g, py.__name__, py.__defaults__, py.__closure__)


def jacobian_jet(model: Model, t: float, y, p, q, order: int = 2) -> list[np.ndarray]:
    """[J0, ..., J_order]: the Taylor coefficients of J(y + s q) in s (see the module's docstring)."""
    fn = getattr(model.module, "jac_inplace", None)
    if fn is None:
        raise AnalysisError(f"{model.name}: no jac_inplace to differentiate (regenerate the model)")
    q = np.asarray(q)
    dtype = complex if np.iscomplexobj(q) else float
    n = model.n_states
    Y = np.empty(n, dtype=object)
    for i in range(n):
        c = np.zeros(order + 1, dtype=dtype)
        c[0], c[1] = y[i], q[i]
        Y[i] = Jet(c)
    out = np.empty((n, n), dtype=object)
    _interpreted(fn)(float(t), Y, np.asarray(p, float), out)
    J = np.zeros((order + 1, n, n), dtype=dtype)
    for i in range(n):
        for j in range(n):
            v = out[i, j]
            if isinstance(v, Jet):
                J[:, i, j] = v.c
            else:
                J[0, i, j] = v
    return list(J)


def differences(model: Model, t: float, y, p, q, h: float = 1e-4) -> list[np.ndarray]:
    """[J0, J1, J2] of J(y + s q) by central differences of the exact Jacobian (the independent check;
    accurate to O(h^2) with rounding of order eps / h^2 in J2).  q real or complex."""
    jac = model.module.jac
    y, p = np.asarray(y, float), np.asarray(p, float)
    q = np.asarray(q)

    def along(d):
        Jp, J0, Jm = (np.asarray(jac(t, y + s * d, p)) for s in (h, 0.0, -h))
        return J0, (Jp - Jm) / (2 * h), (Jp - 2 * J0 + Jm) / (2 * h * h)
    if not np.iscomplexobj(q):
        return list(along(q))
    qr, qi = q.real, q.imag
    J0, Br, Cr = along(qr)
    _, Bi, Ci = along(qi)
    # J(y + s(qr + i qi)): the quadratic term is C(q, q, .)/2 = (C(qr,qr) - C(qi,qi) + 2i C(qr,qi))/2
    _, _, Cs = along(qr + qi)  # C(qr+qi, qr+qi)/2 = (Cr + Ci)/2 + C(qr, qi)
    Cmix = Cs - Cr - Ci  # C(qr, qi, .)
    return [J0, Br + 1j * Bi, Cr - Ci + 1j * Cmix]
