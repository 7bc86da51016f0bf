"""The Taylor series' proof (issue 20 for the `taylor` target of issue 22): `<model>_taylor.c` compiled
with the strict flags, loaded, both exports compared with the checked series program.

`<model>_taylor.c` is compiled with `compiler.STRICT_CFLAGS` (a warning refuses it) together with a probe
that includes `<model>_taylor.h` first and alone (twice: the include guard) and takes both functions'
addresses through pointers of the documented types.  Loaded with ctypes, at the Python check's random
points (`proof.samples()`):

- `<model>_taylor(t, y, p, ORDER, coef)`: row 0 is y itself, row 1 the model's rhs (`proof.expected`),
  and rows 0..ORDER equal the series program run in Python (`pyeval.taylor`, the program `checks` has
  shown equal to the Lie derivatives of the printed rhs and, over a step, to mpmath's odefun) row by row;
- `<model>_jet(t, tdot, ycoef, p, ORDER, fcoef)` along a random input series equals `pyeval.jet`, and with
  ycoef = (y, 0, ...) and tdot = 0 its row 0 is the rhs and every other row 0;
- both write exactly (ORDER + 1) x N values (guard cells; cells start as NaN), leave their inputs alone,
  and refuse an order outside 0..<MODEL>_TAYLOR_MAX_ORDER (return 1, nothing written);
- every coefficient row is bitwise exchange-invariant where identical balls coincide.

The frame (`codegen.passes.proof`: Proof, Guarded, the strict compiler) is branch `proven`'s (issue 20); the
hook `TaylorTarget.prove` is what `regenerate` calls once it proves every target before writing.
"""

from __future__ import annotations

import ctypes

import numpy as np

from ... import compiler
from .pyeval import jet as series_jet, taylor as series_taylor

ORDER = 6  # rows compared (the engine's orders reuse the same recurrences with a larger K)
SERIES_TOLERANCE = 1e-10  # a row of C coefficients against the Python program's, norm-wise relative
DOUBLE_P = ctypes.c_void_p


def _probe(name: str) -> str:
    return (f'#include "{name}_taylor.h"\n#include "{name}_taylor.h"\n'
            f"int (*const proof_taylor)(double, const double *, const double *, int, double *) = {name}_taylor;\n"
            f"int (*const proof_jet)(double, double, const double *, const double *, int, double *) = {name}_jet;\n"
            f"const long proof_taylor_macros[] = {{ {name.upper()}_TAYLOR_N_STATES, {name.upper()}_TAYLOR_MAX_ORDER }};\n")


class Series:
    """The loaded library: `taylor(t, y, p, order)` and `jet(t, tdot, ycoef, p, order)` on guarded outputs."""

    def __init__(self, proof, path, ir):
        self.proof, self.name, self.n = proof, ir.name, ir.n_states
        self.cdll = ctypes.CDLL(str(path))
        self._taylor = getattr(self.cdll, f"{self.name}_taylor")
        self._taylor.restype = ctypes.c_int
        self._taylor.argtypes = [ctypes.c_double, DOUBLE_P, DOUBLE_P, ctypes.c_int, DOUBLE_P]
        self._jet = getattr(self.cdll, f"{self.name}_jet")
        self._jet.restype = ctypes.c_int
        self._jet.argtypes = [ctypes.c_double, ctypes.c_double, DOUBLE_P, DOUBLE_P, ctypes.c_int, DOUBLE_P]

    def taylor(self, t: float, y, p, order: int):
        from ...passes.proof import Guarded

        y, p = np.array(y, float), np.array(p, float)
        y0, p0 = y.copy(), p.copy()
        out = Guarded((max(order, 0) + 1) * self.n)
        code = self._taylor(float(t), y.ctypes.data, p.ctypes.data, int(order), out.inner.ctypes.data)
        self._intact(f"{self.name}_taylor", out, (y, p), (y0, p0))
        return code, out

    def jet(self, t: float, tdot: float, ycoef, p, order: int):
        from ...passes.proof import Guarded

        yc, p = np.array(ycoef, float).ravel(), np.array(p, float)
        yc0, p0 = yc.copy(), p.copy()
        out = Guarded((max(order, 0) + 1) * self.n)
        code = self._jet(float(t), float(tdot), yc.ctypes.data, p.ctypes.data, int(order), out.inner.ctypes.data)
        self._intact(f"{self.name}_jet", out, (yc, p), (yc0, p0))
        return code, out

    def _intact(self, what, out, now, before):
        self.proof.require(out.intact(), f"{what} writes outside its {out.size} output values")
        self.proof.require(all(np.array_equal(a, b) for a, b in zip(now, before)), f"{what} changes its inputs")


def _rows(proof, what: str, got, want) -> None:
    got, want = np.asarray(got, float), np.asarray(want, float)
    for k in range(want.shape[0]):
        proof.compare(f"{what} row {k}", got[k], want[k], SERIES_TOLERANCE)


def _compare(proof, lib: Series, ir, prog, max_order: int) -> None:
    m, n = ir.name, ir.n_states
    rng = np.random.default_rng(7)
    for t, y, p in proof.samples():
        code, out = lib.taylor(t, y, p, ORDER)
        proof.require(code == 0, f"{m}_taylor returns {code} at order {ORDER}")
        rows = out.inner.reshape(ORDER + 1, n)
        proof.require(np.array_equal(rows[0], np.asarray(y, float)), f"{m}_taylor's row 0 is not the state")
        proof.compare(f"{m}_taylor row 1 (the rhs)", rows[1], proof.expected("rhs", t, y, p))
        _rows(proof, f"{m}_taylor", rows, series_taylor(prog, t, list(map(float, y)), list(map(float, p)), ORDER))
        # the jet along a random series (the time moving too), and along a constant one
        ycoef = np.vstack([np.asarray(y, float), rng.uniform(-1.0, 1.0, (ORDER, n)) / np.arange(1, ORDER + 1)[:, None]])
        tdot = float(rng.uniform(0.5, 1.5))
        code, out = lib.jet(t, tdot, ycoef, p, ORDER)
        proof.require(code == 0, f"{m}_jet returns {code} at order {ORDER}")
        want = series_jet(prog, t, [list(map(float, r)) for r in ycoef], list(map(float, p)), ORDER, tdot=tdot)
        _rows(proof, f"{m}_jet", out.inner.reshape(ORDER + 1, n), want)
        flat = np.zeros((ORDER + 1, n))
        flat[0] = y
        code, out = lib.jet(t, 0.0, flat, p, ORDER)
        rows = out.inner.reshape(ORDER + 1, n)
        proof.compare(f"{m}_jet row 0 (the rhs)", rows[0], proof.expected("rhs", t, y, p))
        if ir.autonomous:
            proof.require(not np.any(rows[1:]), f"{m}_jet along a constant series has a nonzero row above 0")
    t, y, p = proof.samples()[0]
    for order in (-1, max_order + 1):
        for what, (code, out) in ((f"{m}_taylor", lib.taylor(t, y, p, order)),
                                  (f"{m}_jet", lib.jet(t, 0.0, np.asarray(y, float), p, order))):
            proof.require(code == 1 and bool(np.all(np.isnan(out.inner))),
                          f"{what} at order {order} returns {code} or writes (orders 0..{max_order} only)")
    for k in range(1, ORDER + 1):
        proof.exchange_bitwise(f"{m}_taylor row {k}",
                               lambda t, y, p, k=k: lib.taylor(t, y, p, ORDER)[1].inner.reshape(ORDER + 1, n)[k])


def prove(target, proof) -> None:
    compiler.require("gcc", "taylor")
    ir = proof.model(target)
    prog, why = target.program(ir)
    proof.require(prog is not None, f"no series form ({why})")
    rel_c = proof.file(target, "taylor/taylor.c.j2")
    proof.file(target, "taylor/taylor.h.j2")
    obj = proof.c_object(rel_c)
    build = proof.build_dir()
    (build / "taylor_probe.c").write_text(_probe(ir.name))
    probe = compiler.compile_object(build / "taylor_probe.c", build / "taylor_probe.o",
                                    f"{ir.name}_taylor.h (included alone)", include=[proof.path(rel_c).parent])
    so = compiler.link([obj, probe], build / f"lib{ir.name}_taylor.so", f"the library of {rel_c}", shared=True)
    proof.expected_all()

    def run():
        lib = Series(proof, so, ir)
        macros = list((ctypes.c_long * 2).in_dll(lib.cdll, "proof_taylor_macros"))
        want = [ir.n_states, target.max_order]
        proof.require(macros == want, f"{ir.name}_taylor.h's N_STATES, MAX_ORDER are {macros}, not {want}")
        _compare(proof, lib, ir, prog, target.max_order)
    proof.isolated(f"the library of {rel_c}", run)
