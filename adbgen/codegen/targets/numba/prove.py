"""The numba module's proof (issue 20): the rendered `<model>/__init__.py` executed and its public API run.

The module is executed with numba's JIT disabled (`numba.config.DISABLE_JIT` while it is imported:
every ``@njit`` function is then the Python function numba would compile, the same source), so a
proof costs milliseconds instead of numba's seconds of compilation per model; the tests compile the
committed modules.  Shown at the Python check's random points, against `Proof.expected`:

- the wrappers users call (`rhs`, `jac`, `jac_p`, `mass_matrix`, `forcing`) and the ``*_inplace``
  kernels, each output a fresh array of the declared shape;
- `params()` returns a fresh array (changing it leaves DEFAULTS alone), sets what it is given and
  refuses an unknown name; `state_index` inverts STATE_NAMES and refuses an unknown name;
- the metadata (names, units, defaults, start, structure, SOURCE_HASH and every field of the
  self-description) equals the intermediate form's;
- `measure`, `measures_inplace`, `measures_along` equal the self-description's measures, and
  `steady_state` its closed forms at random parameters (None exactly where they give none);
- identical balls' accelerations are bitwise equal where the balls coincide.
"""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import numpy as np

from ...passes.checks import _parameter_points
from ...plain_python import compile_measures, compile_steady_states
from ...render import param_domain, source_hash


def load(path: Path, alias: str):
    """The module at `path` executed with numba's JIT off (not left in sys.modules)."""
    import numba

    spec = importlib.util.spec_from_file_location(alias, path, submodule_search_locations=[str(path.parent)])
    module = importlib.util.module_from_spec(spec)
    saved = numba.config.DISABLE_JIT
    numba.config.DISABLE_JIT = True
    sys.modules[alias] = module
    try:
        spec.loader.exec_module(module)
    finally:
        numba.config.DISABLE_JIT = saved
        sys.modules.pop(alias, None)
    return module


def _metadata(proof, m, ir) -> None:
    expect = {
        "NAME": ir.name, "TITLE": ir.title, "REFERENCE": ir.reference, "SOURCE_HASH": source_hash(ir),
        "N_BALLS": ir.n_balls, "N_STATES": ir.n_states, "AUTONOMOUS": ir.autonomous,
        "STATE_NAMES": ir.state_names, "PARAM_NAMES": ir.parameter_names,
        "PARAM_UNITS": tuple(p.unit for p in ir.parameters),
        "PARAM_DESCRIPTIONS": tuple(p.description for p in ir.parameters),
        "CORE": ir.core, "LEAVES": ir.leaves, "MASS_PATTERN": ir.mass_pattern,
        "PARAM_DOMAINS": tuple(param_domain(p.symbol) for p in ir.parameters),
    }
    d = ir.description
    if d is not None:
        expect.update({
            "FAMILY": d.family, "KIND": d.kind, "TIME_UNIT": d.time_unit, "STATE_UNITS": d.state_units,
            "STATE_ROLES": d.roles, "ANGLES": d.angles, "AMPLITUDE": d.amplitude, "MEASURES": d.measure_names,
            "N_MEASURES": len(d.measure_names), "RESIDUAL_MEASURE": d.residual, "FORCING_FREQUENCY": d.forcing_frequency,
            "SYMMETRIES": tuple(dict(s) for s in d.symmetries),
            "PARAMETER_SETS": {name: dict(values) for name, values in d.parameter_sets},
            "SCALES": dict(d.scales), "STEADY_STATES": d.labels,
            "STEADY_STATE_NOTES": {label: note for label, note, _, _ in d.steady_states},
        })
    for key, want in expect.items():
        got = getattr(m, key, "<missing>")
        if key == "SYMMETRIES" and got != "<missing>":
            got = tuple({k: tuple(v) if isinstance(v, (list, tuple)) else v for k, v in s.items()} for s in got)
            want = tuple({k: tuple(v) if isinstance(v, (list, tuple)) else v for k, v in s.items()} for s in want)
        proof.require(got == want, f"{key} is {got!r}, the model's is {want!r}")
    defaults = np.array([p.default for p in ir.parameters], dtype=float)
    proof.require(isinstance(m.DEFAULTS, np.ndarray) and np.array_equal(m.DEFAULTS, defaults),
                  f"DEFAULTS is {m.DEFAULTS!r}, the model's are {defaults!r}")
    for key, want in (("START", ir.start), ("START_PARAMETERS", ir.start_parameters)):
        got = getattr(m, key)
        same = got is None if want is None else (got is not None and np.array_equal(got, np.array(want, float)))
        proof.require(same, f"{key} is {got!r}, the model's is {want!r}")


def _api(proof, m, ir) -> None:
    names = ir.state_names
    for k, name in enumerate(names):
        proof.require(m.state_index(name) == k, f"state_index({name!r}) is {m.state_index(name)!r}, not {k}")
    for fn, bad in ((m.state_index, "no_such_state"), (m.params, None)):
        try:
            fn(bad) if bad else fn(no_such_parameter=1.0)
        except KeyError:
            pass
        else:
            proof.fail(f"{fn.__name__} accepts an unknown name")
    p = m.params()
    proof.require(p is not m.DEFAULTS and not np.shares_memory(p, m.DEFAULTS) and np.array_equal(p, m.DEFAULTS),
                  "params() does not return a fresh copy of DEFAULTS")
    p[:] = np.nan
    proof.require(not np.isnan(m.DEFAULTS).any() and np.array_equal(m.params(), m.DEFAULTS),
                  "changing what params() returned changed DEFAULTS")
    for k, name in enumerate(ir.parameter_names):
        q = m.params(**{name: 0.125 + k})
        want = m.DEFAULTS.copy()
        want[k] = 0.125 + k
        proof.require(np.array_equal(q, want), f"params({name}=...) does not set parameter {k}")


def _functions(proof, m, ir) -> None:
    S, P, N = ir.n_states, len(ir.parameters), ir.n_coordinates
    shapes = {"rhs": (S,), "jac": (S, S), "jac_p": (S, P), "mass": (N, N), "forcing": (N,)}
    wrappers = {"rhs": m.rhs, "jac": m.jac, "jac_p": m.jac_p, "mass": m.mass_matrix, "forcing": m.forcing}
    inplace = {"rhs": m.rhs_inplace, "jac": m.jac_inplace, "jac_p": m.jac_p_inplace}
    for t, y, p in proof.samples():
        y0, p0 = y.copy(), p.copy()
        for which, fn in wrappers.items():
            want = proof.expected(which, t, y, p)
            got = fn(t, y, p)
            proof.require(isinstance(got, np.ndarray) and got.shape == shapes[which],
                          f"{fn.__name__} returned shape {np.shape(got)}, not {shapes[which]}")
            proof.compare(fn.__name__, np.ravel(got), want)
            proof.require(fn(t, y, p) is not got, f"{fn.__name__} returns the same array twice")
            if which in inplace:
                out = np.full(shapes[which], np.nan)
                inplace[which](t, y, p, out)
                proof.compare(f"{which}_inplace", out.ravel(), want)
        proof.require(np.array_equal(y, y0) and np.array_equal(p, p0), "a function changed its arguments y or p")
    proof.exchange_bitwise("rhs", m.rhs)


def _description(proof, m, ir) -> None:
    d = ir.description
    if d is None:
        return
    if d.measure_names:
        measures = compile_measures(ir)
        ts, cols = [], []
        for t, y, p in proof.samples():
            want = measures(t, y, p)
            out = np.full(len(d.measure_names), np.nan)
            m.measures_inplace(t, y, p, out)
            proof.compare("measures_inplace", out, want)
            for k, name in enumerate(d.measure_names):
                proof.compare(f"measure({name!r})", [m.measure(name, t, y, p)], [want[k]])
            ts.append(t)
            cols.append(y)
        t, y, p = proof.samples()[0]
        along = m.measures_along(np.array(ts), np.array(cols).T.copy(), p)
        want = np.array([measures(tk, yk, p) for tk, yk in zip(ts, cols)]).T
        proof.compare("measures_along", along, want)
    if d.steady_states:
        solvers = compile_steady_states(ir)
        for p in _parameter_points(ir, 8, 14):
            for label in d.labels:
                want, got = solvers[label](p), m.steady_state(label, p)
                proof.require((want is None) == (got is None),
                              f"steady_state({label!r}) is {'None' if got is None else 'given'} where its closed form "
                              f"{'gives none' if want is None else 'gives one'}")
                if want is not None:
                    proof.compare(f"steady_state({label!r})", got, want)


def prove(target, proof) -> None:
    ir = proof.model(target)
    path = proof.path(proof.file(target, "numba/module.py.j2"))
    m = load(path, f"_adbgen_proof_{ir.name}")
    _metadata(proof, m, ir)
    _api(proof, m, ir)
    _functions(proof, m, ir)
    _description(proof, m, ir)
    if proof.form == "loops" and ir.loops is not None:
        text = proof.files[proof.file(target, "numba/module.py.j2")]
        body = text.split("def rhs_inplace", 1)[1].split("\ndef ", 1)[0]
        proof.require(f"for i in range({ir.n_balls}):" in body, "rhs_inplace is not in the loop form requested")
