"""The AUTO-07p files' proof (issue 20): the user file through AUTO's calling convention, the constants
parsed and checked field by field.

The user file is compiled with `compiler.STRICT_CFLAGS` inside `harness.c`, which calls func, stpnt and
pvls through AUTO's own table of function types (`user`, auto_f2c.h).  At the Python check's random
points (for a forced model: its oscillator extension's, the oscillator on and off its cycle), with
every PAR cell that is not a model parameter NAN (func must not read AUTO's own PAR(11)-PAR(14)):

- func with IJAC = 0 writes F = `Proof.expected`'s rhs and leaves dfdu and dfdp alone; IJAC = 1 adds
  dF/dU (column-major: ARRAY2D(dfdu, i, j) = dF_i/dU_j) = jac; IJAC = 2 adds dF/dPAR (column
  APAR(k) = jac_p's column k) and leaves the other columns alone; a wrong NDIM returns non-zero;
- where the start lies on the continuum of balanced states (thesis (3.6), n >= 3), F and dF/dU carry
  the regularising term of templates/auto/_family.j2: F's is computed here from the thesis' tangent
  (v1_j, v2_j, e_j) at the random states (h = phi_j - phi_j(stpnt) != 0 there), dF/dU's by the complex
  step of that term (no formula of the template's derivative is restated);
- stpnt writes the start (every state; a forced model's oscillator at (sin, cos)(2 pi t) and the period
  PAR(11) = 2 pi / frequency) and the start's parameters, and nothing else; pvls writes the rotor's
  amplitude (the hypot of the first two core states) into one PAR cell, nothing else;
- c.<model> (and c.<model>.2) parsed: NDIM, IPS, IRS, ICP (the continued parameter's PAR index from
  the family's continuation, the period for periodic orbits, and the cell pvls writes), IPLT, JAC, NBC,
  NINT, UZSTOP, the direction of DS and the stages, against what the target decided (`context`) and
  what that must be for this model.
"""

from __future__ import annotations

import ast
import ctypes
import math
import os
import sys
from contextlib import contextmanager
from pathlib import Path

import numpy as np

from ... import compiler
from ...passes.proof import GUARD, SENTINEL, Guarded
from .dialect import par_index

HERE = Path(__file__).resolve().parent
NPAR = 36  # AUTO-07p's PAR array (NPARX)
TWO_PI = 2 * math.pi


@contextmanager
def quiet_stderr():
    """File descriptor 2 to /dev/null for the duration (what the C code prints there is not the proof's)."""
    sys.stderr.flush()
    saved = os.dup(2)
    null = os.open(os.devnull, os.O_WRONLY)
    try:
        os.dup2(null, 2)
        yield
    finally:
        os.dup2(saved, 2)
        os.close(saved)
        os.close(null)


class UserFile:
    def __init__(self, path: Path, ndim: int, npar: int):
        self.cdll, self.ndim, self.npar = ctypes.CDLL(str(path)), ndim, npar
        vp = ctypes.c_void_p
        self.func = self.cdll.proof_func
        self.func.restype, self.func.argtypes = ctypes.c_int, [ctypes.c_long, vp, vp, ctypes.c_long, vp, vp, vp]
        self.stpnt = self.cdll.proof_stpnt
        self.stpnt.restype, self.stpnt.argtypes = ctypes.c_int, [ctypes.c_long, ctypes.c_double, vp, vp]
        self.pvls = self.cdll.proof_pvls
        self.pvls.restype, self.pvls.argtypes = ctypes.c_int, [ctypes.c_long, vp, vp]

    def close(self):
        import _ctypes

        _ctypes.dlclose(self.cdll._handle)

    def call(self, u, par, ijac: int, ndim: int | None = None):
        """(return value, f, dfdu, dfdp) as Guarded arrays (dfdu, dfdp prefilled with SENTINEL)."""
        n = self.ndim
        u, par = np.array(u, dtype=float), np.array(par, dtype=float)
        f, dfdu, dfdp = Guarded(n), Guarded(n * n, fill=SENTINEL), Guarded(n * self.npar, fill=SENTINEL)
        r = self.func(ndim or n, u.ctypes.data, par.ctypes.data, ijac, f.inner.ctypes.data, dfdu.inner.ctypes.data,
                      dfdp.inner.ctypes.data)
        return r, f, dfdu, dfdp


def _par(model, p, npar: int) -> np.ndarray:
    par = np.full(npar, np.nan)
    for k, v in enumerate(p):
        par[par_index(k)] = v
    return par


def _family_term(model, ctx, u):
    """F's regularising term at u (complex u: its complex-step derivative), as the thesis' tangent gives
    it: for each free angle j, h_j = phi_j - phi_j(stpnt), F(phi_1) -= s v1_j h_j, F(phi_2) -= s v2_j h_j,
    F(phi_j) -= s h_j, v1_j = sin(phi_2 - phi_j)/sin(phi_1 - phi_2), v2_j = sin(phi_j - phi_1)/sin(phi_1 - phi_2)."""
    names = model.state_names
    ia, ib = names.index(model.leaves[0]), names.index(model.leaves[1])
    sigma = ctx["family_sigma"]
    out = np.zeros(len(u), dtype=complex)
    s12 = np.sin(u[ia] - u[ib])
    for leaf in model.leaves[2:]:
        j = names.index(leaf)
        h = u[j] - model.start[j]
        out[ia] -= sigma * np.sin(u[ib] - u[j]) / s12 * h
        out[ib] -= sigma * np.sin(u[j] - u[ia]) / s12 * h
        out[j] -= sigma * h
    return out


def _family_jacobian(model, ctx, u) -> np.ndarray:
    n = len(u)
    J = np.empty((n, n))
    for k in range(n):
        z = u.astype(complex)
        z[k] += 1e-30j
        J[:, k] = _family_term(model, ctx, z).imag / 1e-30
    return J


def _func(proof, lib: UserFile, model, ctx) -> None:
    n, P, npar = model.n_states, len(model.parameters), lib.npar
    name = f"{model.name}.c func"
    columns = [par_index(k) for k in range(P)]
    if ctx["family"]:
        # thesis (3.6)'s continuum leaves n - 2 zero eigenvalues; the term moves them to -FAMILY_SIGMA, which
        # AUTO's Newton steps need nonzero (sigma = 0 writes the singular problem) and negative (stable)
        sigma = ctx["family_sigma"]
        proof.require(np.isfinite(sigma) and sigma > 0, f"{name}: the continuum's regularisation FAMILY_SIGMA = "
                      f"{sigma!r} must be a positive number (it moves the n - 2 zero eigenvalues to -FAMILY_SIGMA)")
    for t, u, p in proof.samples(model):
        par = _par(model, p, npar)
        rhs = proof.expected("rhs", t, u, p, model)
        jac = proof.expected("jac", t, u, p, model).reshape(n, n)
        if ctx["family"]:
            rhs = rhs + _family_term(model, ctx, u).real
            jac = jac + _family_jacobian(model, ctx, u)
        for ijac in (0, 1, 2):
            r, f, dfdu, dfdp = lib.call(u, par, ijac)
            proof.require(r == 0, f"{name} returns {r} with IJAC = {ijac}")
            proof.require(f.intact() and dfdu.intact() and dfdp.intact(), f"{name} writes outside its arrays (IJAC = {ijac})")
            proof.compare(f"{name} F (IJAC = {ijac})", f.inner, rhs)
            if ijac == 0:
                proof.require(bool(np.all(dfdu.inner == SENTINEL)), f"{name} writes dfdu with IJAC = 0")
            else:
                proof.compare(f"{name} dfdu (column-major, IJAC = {ijac})", dfdu.inner.reshape(n, n).T, jac)
            cols = dfdp.inner.reshape(npar, n).T
            if ijac < 2:
                proof.require(bool(np.all(cols == SENTINEL)), f"{name} writes dfdp with IJAC = {ijac}")
            else:
                proof.compare(f"{name} dfdp (columns APAR(k), IJAC = 2)", cols[:, columns],
                              proof.expected("jac_p", t, u, p, model).reshape(n, P))
                others = [c for c in range(npar) if c not in columns]
                proof.require(bool(np.all(cols[:, others] == SENTINEL)),
                              f"{name} writes dfdp columns that are not model parameters")
    t, u, p = proof.samples(model)[0]
    with quiet_stderr():  # func says what is wrong on stderr
        r, _, _, _ = lib.call(u, _par(model, p, npar), 0, ndim=n + 1)
    proof.require(r != 0, f"{name} accepts NDIM = {n + 1} (the model has {n} states)")
    if not ctx["family"]:  # the regularisation is tied to one member of the continuum, not to every exchange

        def f_of(t, u, p):
            r, f, _, _ = lib.call(u, _par(model, p, npar), 0)
            return f.inner.copy()
        proof.exchange_bitwise(name, f_of, model)


def _stpnt_pvls(proof, lib: UserFile, model, ctx) -> None:
    n, npar = model.n_states, lib.npar
    forced = ctx["forced"]
    start = np.array(model.start if model.start is not None else np.zeros(n), dtype=float)
    values = model.start_parameters if model.start is not None else [q.default for q in model.parameters]
    for t in (0.0, 0.3):
        u, par = Guarded(n), Guarded(npar)
        r = lib.stpnt(n, t, u.inner.ctypes.data, par.inner.ctypes.data)
        proof.require(r == 0 and u.intact() and par.intact(), f"stpnt returns {r} or writes outside U and PAR")
        want = start.copy()
        if forced:
            s, c = ctx["osc"]
            want[s], want[c] = math.sin(TWO_PI * t), math.cos(TWO_PI * t)
        proof.compare(f"stpnt's U at t = {t}", u.inner, want, tolerance=1e-15)
        expect = np.full(npar, np.nan)
        for k, v in enumerate(values):
            expect[par_index(k)] = v
        if forced:
            expect[10] = TWO_PI / values[ctx["stage2"]]
        written = ~np.isnan(expect)
        proof.require(np.array_equal(np.isnan(par.inner), ~written), "stpnt writes other PAR cells than the model's "
                      f"parameters{' and the period' if forced else ''}: {np.flatnonzero(~np.isnan(par.inner)).tolist()}")
        proof.compare("stpnt's PAR", par.inner[written], expect[written], tolerance=1e-15)
    u = np.random.default_rng(7).uniform(-2, 2, n)
    par = Guarded(npar)
    r = lib.pvls(n, u.ctypes.data, par.inner.ctypes.data)
    proof.require(r == 0 and par.intact(), f"pvls returns {r} or writes outside PAR")
    written = np.flatnonzero(~np.isnan(par.inner)).tolist()
    if ctx["amplitude"] is None:
        proof.require(written == [], f"pvls writes PAR cells {written} (the model has no amplitude)")
        return
    a, b = ctx["amplitude"]
    proof.require(written == [ctx["npar_amp"]], f"pvls writes PAR cells {written}, not [{ctx['npar_amp']}] only")
    proof.compare("pvls's amplitude", [par.inner[ctx["npar_amp"]]], [math.hypot(u[a], u[b])], tolerance=1e-15)


def parse_constants(text: str) -> dict:
    """AUTO-07p's constants file as {key: value} ('KEY = value, KEY = value' lines, '#' comments)."""
    out = {}
    for raw in text.splitlines():
        line = raw.split("#", 1)[0].strip()
        if not line:
            continue
        items, depth, quote, current = [], 0, None, ""
        for ch in line:
            if quote:
                quote = None if ch == quote else quote
            elif ch in "'\"":
                quote = ch
            elif ch in "[{(":
                depth += 1
            elif ch in "]})":
                depth -= 1
            if ch == "," and depth == 0 and not quote:
                items.append(current)
                current = ""
            else:
                current += ch
        items.append(current)
        for item in items:
            key, sep, value = item.partition("=")
            if not sep:
                raise ValueError(f"not 'KEY = value': {item.strip()!r}")
            key = key.strip()
            if key in out:
                raise ValueError(f"{key} given twice")
            out[key] = ast.literal_eval(value.strip())
    return out


def _constants(proof, target, model, ctx) -> None:
    """Each stage's constants against the target's decisions (context) and what they must be."""
    names = model.parameter_names
    cont = model.continuation
    amp = ctx["npar_amp"] + 1
    # the decisions themselves, against the model: the family's continuation and the mapping of PAR
    proof.require(ctx["icp"] == names.index(cont.parameter), f"the target continues parameter {ctx['icp']}, "
                  f"the family's continuation {cont.parameter!r} is parameter {names.index(cont.parameter)}")
    proof.require(ctx["npar_amp"] == par_index(len(names)), "the amplitude's PAR cell is not the one after the parameters'")
    core = tuple(model.state_names.index(c) for c in model.core[:2]) if len(model.core) >= 2 else None
    proof.require(ctx["amplitude"] == core, f"the amplitude states {ctx['amplitude']} are not the rotor's {core}")
    forced = bool(model.forcing_frequency)
    stages = (2 if cont.second else 1) if forced else 1
    proof.require(ctx["forced"] == forced and ctx.get("stages", 1) == stages,
                  f"the target decided {ctx.get('stages', 1)} stage(s), the continuation has {stages}")
    rendered = [rel for tpl, rel in target.files if tpl.startswith("auto/constants") and rel.format(name=model.name)
                in proof.files]
    proof.require(len(rendered) == stages, f"{len(rendered)} constants file(s) rendered for {stages} stage(s)")
    p1 = par_index(ctx["icp"]) + 1
    for stage in range(1, stages + 1):
        rel = proof.file(target, "auto/constants.j2" if stage == 1 else "auto/constants_stage2.j2")
        try:
            c = parse_constants(proof.files[rel])
        except (ValueError, SyntaxError) as exc:
            proof.fail(f"{rel} is not an AUTO-07p constants file: {exc}")
        what = f"{Path(rel).name}:"
        # IPLT = 0: fort.7's second column is AUTO's L2-NORM, which adbgen's readers of fort.7 expect (the
        # amplitude is the last ICP); JAC = 1: func fills dfdu and dfdp; NBC = NINT = 0: bcnd, icnd are empty
        proof.require(ctx["iplt"] == 0, f"the target decided IPLT = {ctx['iplt']}: fort.7 must keep its L2-NORM column")
        # ILP = 1, ISP = 2: folds and every bifurcation detected (the LP/BP/HB/PD/TR labels adbgen's scans read);
        # ISW = 1: a normal start (not a branch switch)
        expect = {"NDIM": model.n_states, "IPS": 2 if forced else 1, "IPLT": 0, "JAC": 1, "NBC": 0,
                  "NINT": 0, "IRS": 0 if stage == 1 else ctx["restart_label"], "ILP": 1, "ISP": 2, "ISW": 1}
        if forced:
            first = p1 if stage == 1 else par_index(ctx["stage2"]) + 1
            expect["ICP"] = [first, 11, amp]
        else:
            first = p1
            expect["ICP"] = [p1, amp]
        for key, want in expect.items():
            proof.require(c.get(key) == want, f"{what} {key} = {c.get(key)!r}, the target decided {want!r}")
        if stage == 2:
            proof.require(c.get("s") == model.name, f"{what} restarts from s = {c.get('s')!r}, not {model.name!r}")
        ds, stop = c.get("DS"), c.get("UZSTOP")
        proof.require(isinstance(ds, (int, float)) and ds != 0, f"{what} DS = {ds!r}")
        if not forced or stages == 1:
            down = ctx["down"]
        elif stage == 1:
            down = model.parameters[ctx["icp"]].default < ctx["start_value"]
        else:
            down = True
        proof.require((ds < 0) == down, f"{what} DS = {ds} continues {'up' if ds > 0 else 'down'}, the target "
                                        f"decided {'down' if down else 'up'}")
        if forced and stages == 2 and stage == 1:
            want_stop = {first: model.parameters[ctx["icp"]].default}
            proof.require(stop == want_stop, f"{what} UZSTOP = {stop!r}, not {want_stop!r} (stage 1 ends at the default)")
        elif forced:
            w0 = model.parameters[ctx["stage2"]].default if stages == 2 else ctx["start_value"]
            ok = isinstance(stop, dict) and list(stop) == [first] and len(stop[first]) == 2 and stop[first][0] < w0 < stop[first][1]
            proof.require(ok, f"{what} UZSTOP = {stop!r} is not a window about {w0} in PAR({first})")
        elif ctx["stop"]:
            want_stop = {first: [float(v) for v in ctx["stop"]]}
            proof.require(stop == want_stop and list(ctx["stop"]) == list(cont.stop),
                          f"{what} UZSTOP = {stop!r}, the family's stop is {cont.stop!r}")
        else:
            proof.require(stop is None, f"{what} UZSTOP = {stop!r} where the family gives no stop")


def prove(target, proof) -> None:
    compiler.require("auto", "auto")
    model = proof.model(target)
    ctx = target.context(model)
    rel = proof.file(target, "auto/user.c.j2")
    build = proof.build_dir()
    name = Path(rel).name
    obj = compiler.compile_object(HERE / "harness.c", build / "auto_harness.o", name,
                                  include=[proof.path(rel).parent, compiler.auto_include()],
                                  defines=[f'USER_FILE="{name}"'])
    so = compiler.link([obj], build / "libauto_proof.so", name, shared=True)
    npar = max(NPAR, ctx["npar_amp"] + 1 + GUARD)
    proof.expected_all(model)

    def run():
        lib = UserFile(so, model.n_states, npar)
        _func(proof, lib, model, ctx)
        _stpnt_pvls(proof, lib, model, ctx)
    proof.isolated(name, run)
    _constants(proof, target, model, ctx)
    if proof.form == "loops":
        body = proof.files[rel].split("int func(", 1)[1].split("if (ijac == 0)", 1)[0]
        proof.require(f"for (int i = 0; i < {model.n_balls}; ++i) {{" in body, "func is not in the loop form requested")
