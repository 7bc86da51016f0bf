"""The Taylor target (adbgen/codegen/targets/taylor/): the series program against independent
references, the emitted C against the series program, the jet as exact directional derivatives, and the
loop form kept (the text does not grow with n).
"""

from __future__ import annotations

import ctypes
import re
import subprocess

import mpmath
import numpy as np
import pytest
import sympy as sp

from adbgen import families
from adbgen.codegen.passes.checks import CheckFailed
from adbgen.codegen.ir.loops import Kernel, Let, Put, Pos
from adbgen.codegen.ir.model import TIME
from adbgen.codegen.regenerate import DEFAULT_OUT
from adbgen.codegen.spec import build as build_ir
from adbgen.codegen.targets.taylor import checks, pyeval, reference
from adbgen.codegen.targets.taylor.series import Decomposer, NotSeries, decompose
from toolchain import STRICT_CFLAGS, require_tool, which

SPECS = {s.name: s for f in families.all_families() for s in f.models()}
# one of each kind: rotating frame, fixed frame (sin(omega t)), two-plane, a Piecewise ramp, the Hill
# run-up (log, atan, sqrt, powers of t from t = 0), the torque drive (spin as a state)
KINDS = ["thesis_rotating_n2", "single_plane_fixed_n3", "two_plane_rotating", "two_plane_ramp", "two_plane_hill",
         "two_plane_torque"]
_ir: dict = {}


def ir_of(name):
    if name not in _ir:
        ir = build_ir(SPECS[name])
        _ir[name] = (ir, decompose(ir))
    return _ir[name]


@pytest.mark.parametrize("name", ["thesis_rotating_n2", "two_plane_hill"])
def test_coefficients_are_the_lie_derivatives(name):
    """y_0..y_5 of the series program (double) equal L_f^k y / k! of the printed rhs in 60-digit series
    arithmetic (Maclaurin compositions, no recurrences), t = 0 included (the Hill run-up's powers of t
    at their base 0).  (`adbgen regenerate` runs the same check on every model before writing.)"""
    ir, prog = ir_of(name)
    errors = checks.lie_errors(ir, prog, samples=3, seed=11)
    assert max(errors) <= checks.LIE_TOLERANCE, errors


def test_a_step_agrees_with_odefun():
    """One order-20 step of the series program in 30 digits equals mpmath's odefun to 1e-13 (measured
    ~2e-19)."""
    ir, prog = ir_of("thesis_rotating_n2")
    err, h = checks.step_error(ir, prog, seed=3)
    assert err < checks.STEP_TOLERANCE and h > 0.05


def test_a_wrong_recurrence_is_refused(monkeypatch):
    """Negative control: sin's recurrence with the wrong sign (c_K = +1/K sum j u_j s_{K-j}) fails the
    Lie check from order 2 on, and check_series refuses the model naming the coefficient."""
    ir, prog = ir_of("thesis_rotating_n2")
    original = pyeval._Run.node

    def wrong(self, nd, K, i):
        original(self, nd, K, i)
        if nd.op == "sincos" and K > 0:
            c = self.ser(nd.name2, i)
            c[K] = -c[K]

    monkeypatch.setattr(pyeval._Run, "node", wrong)
    errors = checks.lie_errors(ir, prog, samples=1)
    assert errors[1] < 1e-14 and errors[2] > 1e-3
    with pytest.raises(CheckFailed, match="Taylor coefficient 2 .* Lie derivative"):
        checks.check_series(ir, prog)


def test_the_reference_is_taylors_theorem():
    """The reference's series arithmetic against closed forms: sin(1 + s)^2 / (2 + s) and atan, log,
    exp, sqrt of 1 + s/2 at 40 digits."""
    with mpmath.workdps(40):
        reference.Series.K = 6
        s = reference.Series([1, 1])
        ns = reference._namespace()
        got = (ns.sin(s) * ns.sin(s) / (s + 1)).c
        x = mpmath.mpf(0)
        want = mpmath.taylor(lambda v: mpmath.sin(1 + v) ** 2 / (2 + v), x, 6)
        assert max(abs(a - b) for a, b in zip(got, want)) < mpmath.mpf(10) ** -30
        half = reference.Series([1, mpmath.mpf(1) / 2])
        for fn, ref in ((ns.atan, mpmath.atan), (ns.log, mpmath.log), (ns.exp, mpmath.exp), (ns.sqrt, mpmath.sqrt)):
            want = mpmath.taylor(lambda v: ref(1 + v / 2), x, 6)
            assert max(abs(a - b) for a, b in zip(fn(half).c, want)) < mpmath.mpf(10) ** -30


def test_no_recurrence_for_tan():
    """A function without a recurrence here is refused by name (the target then skips the model)."""
    x, p = sp.Symbol("x", real=True), sp.Symbol("k", real=True)
    k = Kernel((Let(sp.Symbol("w", real=True), sp.tan(x)), Put(Pos(0), None, sp.Symbol("w", real=True))), (1,), False)
    d = Decomposer(k, name="toy", states=[x], params=[p], time=TIME, split=None, n_coordinates=1)
    with pytest.raises(NotSeries, match="tan"):
        d.run()


def test_a_three_branch_piecewise_is_refused_as_no_series():
    """A sign written as Piecewise((1, x > 0), (-1, x < 0), (0, True)) (friction in slip, issue 37) is
    refused with NotSeries, so the target skips the model with a reason (it crashed unpacking before);
    its nested two-branch form is taken."""
    x, p = sp.Symbol("x", real=True), sp.Symbol("k", real=True)
    w = sp.Symbol("w", real=True)
    three = sp.Piecewise((1, x > 0), (-1, x < 0), (0, True))
    two = sp.Piecewise((1, p > 0), (sp.Piecewise((-1, p < 0), (0, True)), True))
    for expr, refused in ((three, True), (two, False)):
        k = Kernel((Let(w, expr * x), Put(Pos(0), None, w)), (1,), False)
        d = Decomposer(k, name="toy", states=[x], params=[p], time=TIME, split=None,
                       n_coordinates=1)
        if refused:
            with pytest.raises(NotSeries, match="two-branch"):
                d.run()
        else:
            d.run()


def test_the_source_does_not_grow_with_n():
    """<model>_taylor.c for n = 2 and n = 4 differ only in numbers and the order of a few operands: one
    loop body per ball quantity, the balls as lanes."""
    def masked(n):
        text = (DEFAULT_OUT / f"thesis_rotating_n{n}" / f"thesis_rotating_n{n}_taylor.c").read_text()
        return re.sub(r"\d+", "#", text.replace(f"thesis_rotating_n{n}", "M"))
    small, large = masked(2), masked(4)
    assert len(small.splitlines()) == len(large.splitlines())
    assert abs(len(small) - len(large)) <= 0.002 * len(small)


# ----------------------------------------------------------------------------------- the emitted C

@pytest.fixture(scope="module")
def taylor_lib(tmp_path_factory):
    """The committed <model>_taylor.c of each kind, compiled with the issue's strict flags."""
    require_tool(which("gcc") is not None, "gcc")
    folder = tmp_path_factory.mktemp("taylor")
    libs = {}

    def get(name):
        if name not in libs:
            src = DEFAULT_OUT / name / f"{name}_taylor.c"
            so = folder / f"lib{name}_taylor.so"
            proc = subprocess.run(["gcc", *STRICT_CFLAGS, "-fPIC", "-shared", str(src), "-o", str(so), "-lm"],
                                  capture_output=True, text=True)
            assert proc.returncode == 0, proc.stderr[:2000]
            libs[name] = ctypes.CDLL(str(so))
        return libs[name]
    return get


def _c_taylor(lib, name, t, y, p, order):
    D = ctypes.POINTER(ctypes.c_double)
    coef = np.zeros((order + 1, len(y)))
    rc = getattr(lib, f"{name}_taylor")(ctypes.c_double(t), np.ascontiguousarray(y).ctypes.data_as(D),
                                         np.ascontiguousarray(p).ctypes.data_as(D), order, coef.ctypes.data_as(D))
    assert rc == 0
    return coef


def _c_jet(lib, name, t, ycoef, p, order, tdot=0.0):
    D = ctypes.POINTER(ctypes.c_double)
    yc = np.zeros((order + 1, ycoef.shape[1]))
    yc[: len(ycoef)] = ycoef
    fc = np.zeros_like(yc)
    rc = getattr(lib, f"{name}_jet")(ctypes.c_double(t), ctypes.c_double(tdot), yc.ctypes.data_as(D),
                                      np.ascontiguousarray(p).ctypes.data_as(D), order, fc.ctypes.data_as(D))
    assert rc == 0
    return fc


@pytest.mark.parametrize("name", KINDS)
def test_c_equals_the_series_program(taylor_lib, name):
    """<model>_taylor and <model>_jet (C, strict flags) equal the series program run in Python, to order
    12, at t = 0 and at later times (both branches of the run-ups' Piecewise laws), to 1e-10 of each
    row's size (the C sums in four partial sums with fused multiply-adds, Python left to right: measured
    up to 1.3e-12 where the fixed frame's rows grow to 1e30 by order 14)."""
    ir, prog = ir_of(name)
    lib = taylor_lib(name)
    rng = np.random.default_rng(5)
    for t in (0.0, 150.0, 7000.0):
        y = rng.uniform(-1, 1, ir.n_states)
        y[: ir.n_coordinates] *= 0.1
        p = np.array([q.default for q in ir.parameters])
        got = _c_taylor(lib, name, t, y, p, 12)
        want = np.array(pyeval.taylor(prog, t, y, p, 12))
        scale = np.maximum(np.max(np.abs(want), axis=1, keepdims=True), 1e-300)
        assert np.max(np.abs(got - want) / scale) < 1e-10, t
        u = rng.uniform(-1, 1, ir.n_states)
        got = _c_jet(lib, name, t, np.array([y, u]), p, 3, tdot=1.0)
        want = np.array(pyeval.jet(prog, t, [y, u], p, 3, tdot=1.0))
        scale = np.maximum(np.max(np.abs(want), axis=1, keepdims=True), 1e-300)
        assert np.max(np.abs(got - want) / scale) < 1e-12, t


@pytest.mark.parametrize("name", ["thesis_rotating_n3", "two_plane_rotating"])
def test_the_jet_gives_directional_derivatives(taylor_lib, name):
    """With y(s) = y0 + s u and a fixed time, row 1 is J u (the generated analytic Jacobian), row 2 is
    D^2 f[u, u] / 2 (central differences of J u along u: 1e-6), row 3 D^3 f[u, u, u] / 6 (differences of
    row 2's)."""
    import importlib

    module = importlib.import_module(f"generated.{name}")
    ir, _ = ir_of(name)
    lib = taylor_lib(name)
    rng = np.random.default_rng(2)
    y = rng.uniform(-1, 1, ir.n_states)
    y[: ir.n_coordinates] *= 0.1
    u = rng.uniform(-1, 1, ir.n_states)
    p = np.array(module.DEFAULTS)
    f = _c_jet(lib, name, 0.0, np.array([y, u]), p, 3)
    np.testing.assert_allclose(f[0], module.rhs(0.0, y, p), rtol=1e-13, atol=1e-15)
    Ju = np.asarray(module.jac(0.0, y, p)) @ u
    np.testing.assert_allclose(f[1], Ju, rtol=1e-12, atol=1e-13 * np.max(np.abs(Ju)))
    h = 1e-4
    d2 = (np.asarray(module.jac(0.0, y + h * u, p)) @ u - np.asarray(module.jac(0.0, y - h * u, p)) @ u) / (2 * h)
    np.testing.assert_allclose(f[2], d2 / 2, atol=1e-6 * np.max(np.abs(d2)))
    row2 = lambda z: _c_jet(lib, name, 0.0, np.array([z, u]), p, 2)[2]  # noqa: E731
    d3 = (row2(y + h * u) - row2(y - h * u)) / (2 * h)  # d/ds (D^2 f[u,u] / 2) = D^3 f[u,u,u] / 2
    np.testing.assert_allclose(f[3], d3 / 3, atol=1e-6 * np.max(np.abs(d3)))


def test_bad_orders_are_refused(taylor_lib):
    lib = taylor_lib("thesis_rotating_n2")
    D = ctypes.POINTER(ctypes.c_double)
    buf = np.zeros(100 * 8)
    y, p = np.zeros(8), np.zeros(5)
    for order in (-1, 33):
        assert lib.thesis_rotating_n2_taylor(ctypes.c_double(0.0), y.ctypes.data_as(D), p.ctypes.data_as(D),
                                             order, buf.ctypes.data_as(D)) == 1


# ---------------------------------------------------------------------------------------- proof (issue 20)

def test_the_series_files_are_proven_and_a_wrong_recurrence_refused(tmp_path, monkeypatch):
    """`regenerate`'s proof of the taylor target (targets/taylor/prove.py): the committed model's files pass;
    the same files with cos's recurrence sign flipped in the C (row 2 on wrong, row 1 = the rhs still right)
    are refused naming the target and the row."""
    from adbgen.codegen import compiler
    from adbgen.codegen.passes import proof as proofs
    from adbgen.codegen.passes.checks import Reference
    from adbgen.codegen.render import render_model
    from adbgen.codegen.spec import build as build_ir
    from adbgen.families.single_plane import models

    require_tool(compiler.missing("gcc") is None, "gcc")
    monkeypatch.setenv("ADBGEN_CACHE", str(tmp_path / "cache"))
    spec = models.thesis_rotating(2)
    system = spec.system()
    ir = build_ir(spec, system)
    ref = Reference.of(system)
    files = render_model(ir, ("taylor",))
    assert proofs.prove_model(ir, files, ("taylor",), "loops", ref)["targets"] == ("taylor",)
    rel = f"{ir.name}/{ir.name}_taylor.c"
    good = "c[K * sc] = -ts_dotj(u, su, s, ss, 1, K, K) * ts_rec[K];"
    assert files[rel].count(good) == 1
    wrong = dict(files, **{rel: files[rel].replace(good, good.replace("= -ts_dotj", "= ts_dotj"))})
    with pytest.raises(proofs.ProofFailed, match=r"^thesis_rotating_n2: taylor files: thesis_rotating_n2_taylor "
                                                 r"row 2 differs from the model"):
        proofs.prove_model(ir, wrong, ("taylor",), "loops", ref)


@pytest.mark.parametrize("name", KINDS)
def test_a_series_keeps_rows_only_where_its_past_is_read(name):
    """A series read only at the order being computed has one row (row 0), never reached through a
    pointer (a convolution's operand) or at another order; the rest keep TS_MAXO + 2 rows.  The values
    are test_c_equals_the_series_program's to check; this checks the layout that makes the difference:
    the two-ball rotor's workspace for an order-20 batch of 8 trajectories fits a 48 kB first-level
    cache (it was 86 kB with every series kept)."""
    text = (DEFAULT_OUT / name / f"{name}_taylor.c").read_text()
    fields = dict(re.findall(r"double ([vb]\d+)\[(TS_MAXO \+ 2|1)\]\[", text))
    single = {k for k, rows in fields.items() if rows == "1"}
    body = text[text.index("_ts_order("):]
    assert single, "every series kept its history"
    for s in single:
        assert f"&w->{s}[0]" not in body and not re.search(rf"w->{s}\[(?!0\])", body), s
    for s in set(fields) - single:
        assert f"&w->{s}[0]" in body or re.search(rf"w->{s}\[(?!K\])", body) or s in text[:text.index("_ts_order(")]


def test_the_batch_workspace_fits_the_first_level_cache():
    text = (DEFAULT_OUT / "thesis_rotating_n2" / "thesis_rotating_n2_taylor.c").read_text()
    nbp, maxo, lanes = 2, 20, 8
    size = 0
    for _, rows, width in re.findall(r"double ([vb]\d+)\[(TS_MAXO \+ 2|1)\]\[(TS_LB|TS_B)\]", text):
        size += (maxo + 2 if rows != "1" else 1) * (nbp * lanes if width == "TS_LB" else lanes) * 8
    assert 20_000 < size < 48 * 1024, size


@pytest.mark.parametrize("name", ["thesis_rotating_n2", "two_plane_rotating", "two_plane_torque"])
def test_products_sharing_an_operand_are_factored(name, monkeypatch):
    """sum_j c_j u v_j is computed as u (sum_j c_j v_j): no linear combination keeps two single-use
    products with a common operand, the ball products drop (two-ball rotor: 13 -> 9 per ball), and the
    series equal the unfactored program's to rounding (order 12, random states, 1e-12 of each row)."""
    from adbgen.codegen.targets.taylor import series

    ir, prog = ir_of(name)
    monkeypatch.setattr(series, "_factor_products", lambda body, nodes, count, ball_const: (body, count))
    plain = decompose(ir)
    monkeypatch.undo()
    muls = lambda q: sum(1 for st in q.walk() if isinstance(st, series.Def) and st.node.op == "mul")  # noqa: E731
    assert muls(prog) < muls(plain)
    if name == "thesis_rotating_n2":
        assert (muls(plain), muls(prog)) == (13, 9)
    uses = series._uses(prog.body, prog.nodes)
    for st in prog.walk():
        if isinstance(st, series.Def) and st.node.op == "lin":
            single = [prog.nodes[a].args for a in st.node.args
                      if prog.nodes[a].op == "mul" and uses.get(a) == 1 and len(set(prog.nodes[a].args)) == 2]
            shared = [u for args in single for u in args]
            assert len(shared) == len(set(shared)), st.node.name
    rng = np.random.default_rng(11)
    p = np.array([q.default for q in ir.parameters])
    for _ in range(3):
        y = rng.uniform(-1, 1, ir.n_states)
        y[: ir.n_coordinates] *= 0.1
        got = np.array(pyeval.taylor(prog, 0.0, y, p, 12))
        want = np.array(pyeval.taylor(plain, 0.0, y, p, 12))
        scale = np.maximum(np.max(np.abs(want), axis=1, keepdims=True), 1e-300)
        assert np.max(np.abs(got - want) / scale) < 1e-12
