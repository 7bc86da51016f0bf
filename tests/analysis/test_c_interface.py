"""The compiled engines' one C interface (engines/c_interface.py, adb_engine.h; issue 33 item 1): every
driver library is opened through the typed mirror, which refuses a library whose structs are laid out
otherwise (negative control: the header compiled with packed structs) and a call with a wrong argument;
and the engines' numbers are the ones the drivers computed before the interface, bit for bit
(data/engine_fingerprints.json, recorded from the drivers before issue 33; on the machine that recorded
them: the engines built for -march=native and glibc's libm are only reproducible there).  One value was
re-recorded since, when the event measures became one implementation (event_measures.h): cyrk-dop853's
peaks are searched on each step's dense output as rk-dop853's are (before: one re-integration over the two
steps around a peak), and the fourth batch trajectory's r_max came out one ulp higher (1.6e-16 relative);
every other value, and every other engine's, is as recorded before the interface."""

from __future__ import annotations

import ctypes
import hashlib
import json
import math
import subprocess
from pathlib import Path

import numpy as np
import pytest

from adbgen.analysis.engines import ENGINES
from adbgen.analysis.engines import c_interface as ci
from adbgen.analysis.engines.compiled import HERE, compiler
from adbgen.analysis.engines.taylor import _machine
from adbgen.analysis.loading import AnalysisError, load_model

FINGERPRINTS = Path(__file__).parent / "data" / "engine_fingerprints.json"
# one engine per driver (and each variant of a driver's build)
ENGINE_NAMES = ("cyrk-dop853", "rk-dop853", "rk-dop853-batch", "cvode-adams", "arkode-dp5", "taylor",
                "taylor-batch", "matlab-ode45")
PHI_A = {"phi_1": math.pi / 3, "phi_2": -math.pi / 3, "phi_3": math.pi}  # problem A (thesis (5.1))
H = 0.02  # r falls below it before t = 120: t_dec is a crossing located on the continuous solution


def _library(tmp_path: Path, *flags: str):
    """adb_engine.h alone compiled into a library with `flags`."""
    src = tmp_path / "abi.c"
    src.write_text('#include "adb_engine.h"\n')
    out = tmp_path / f"abi{len(flags)}.so"
    subprocess.run([compiler(), "-std=gnu99", "-fPIC", "-shared", f"-I{HERE}", *flags, str(src), "-o", str(out)],
                   check=True)
    return out


def test_the_mirror_refuses_a_library_with_another_layout(tmp_path, _needs_gcc):
    """The header as the drivers compile it opens; packed (every double right after an int) it is refused
    in one line naming the first entry that differs."""
    ci.open_library(_library(tmp_path))
    with pytest.raises(AnalysisError) as err:
        ci.open_library(_library(tmp_path, "-fpack-struct=1"))
    assert "\n" not in str(err.value) and "layout differs" in str(err.value)
    lib = ctypes.CDLL(str(_library(tmp_path)))
    planted = ci.layout()
    planted[5] += 8  # adb_settings.step_factor one double later
    with pytest.raises(AnalysisError, match="entry 5"):
        ci.check_layout(lib, "planted", planted)


def _problem():
    m = load_model("thesis_rotating_n3")
    y0 = np.zeros(m.n_states)
    for name, v in PHI_A.items():
        y0[m.state_names.index(name)] = v
    return m, np.asarray(m.params(), float), y0


def test_a_wrong_argument_is_refused_by_ctypes(_needs_gcc):
    """argtypes are declared: a number where the settings' pointer goes is a ctypes.ArgumentError, not a
    crash or a wrong result (the correct call runs)."""
    m, p, y0 = _problem()
    lib = ENGINES["rk-dop853"].library(m)
    s = ci.settings(m, 10.0, 1e-8, 1e-10, 1e-3, 10**6)
    code, *_ = ci.integrate(lib, m, y0, p, s)
    assert ci.STATUS[code] == "success"
    y_end, res = np.zeros(m.n_states), ci.Result()
    with pytest.raises(ctypes.ArgumentError):
        lib.adb_integrate(ci.ptr(y0), ci.ptr(p), 10.0, None, ci.ptr(y_end), ctypes.byref(res))


def _hex(v) -> list[str]:
    return [float(x).hex() for x in np.ravel(np.asarray(v, float))]


def fingerprint(name: str) -> dict:
    """What engine `name` computes on problem A: a kept run (status, r_max, t_dec, final state, counts, a
    digest of the steps), a batch with early stop in two target regions and one without measures, every
    float as hex."""
    m, p, y0 = _problem()
    e = ENGINES[name]
    r = e.run(m, p, y0, 120.0, 1e-7, 1e-9, H, 10**7)
    steps = np.concatenate([np.ravel(r["t"]), np.ravel(r["y"])]).astype(float)
    out = {"run": {"status": r["status"], "r_max": _hex(r["r_max"]), "t_dec": _hex(r["t_dec"]),
                   "y_end": _hex(r["y_end"]), "counts": [int(r["n_rhs"]), int(r["n_steps"])],
                   "steps": hashlib.sha256(steps.tobytes()).hexdigest()}}
    Y0 = np.repeat(y0[None], 4, axis=0)
    Y0[:, list(m.angle_indices)] += np.linspace(-0.5, 0.5, 4)[:, None]
    P = np.repeat(p[None], 4, axis=0)
    targets = () if name == "matlab-ode45" else (
        (r["y_end"], np.full(m.n_states, 3.0)),
        (r["y_end"] + 0.01, 4 * np.eye(m.n_states), np.full((m.n_states,) * 3, 0.1), 0.9))
    b = e.run_many(m, P, Y0, 120.0, 1e-8, 1e-10, H, 10**7, threads=2, check_dt=15.0, targets=targets)
    out["many"] = {k: (list(map(str, b[k])) if k == "status" else _hex(b[k]))
                   for k in ("status", "r_max", "t_dec", "t_last", "t_fail", "y_end", "target", "n_rhs", "n_steps")}
    # without measures or targets: the lane-group steppers (rk_batch_driver.c, taylor_driver.c's batch build)
    c = e.run_many(m, P, Y0, 120.0, 1e-8, 1e-10, H, 10**7, threads=2, measures=False)
    out["lanes"] = {k: (list(map(str, c[k])) if k == "status" else _hex(c[k]))
                    for k in ("status", "t_last", "y_end", "n_rhs", "n_steps")}
    return out


def record() -> dict:
    """The fingerprints of ENGINE_NAMES on this machine (python -c 'import test_c_interface as t;
    t.record()' with the drivers to record from on PYTHONPATH writes FINGERPRINTS)."""
    data = {"machine": _machine(), "engines": {n: fingerprint(n) for n in ENGINE_NAMES}}
    FINGERPRINTS.parent.mkdir(exist_ok=True)
    FINGERPRINTS.write_text(json.dumps(data, indent=1, sort_keys=True) + "\n")
    return data


def differing(expected: dict, got: dict, where: str = "") -> list[str]:
    """The paths at which two fingerprints differ."""
    if isinstance(expected, dict) and isinstance(got, dict):
        return [d for k in sorted(set(expected) | set(got))
                for d in differing(expected.get(k), got.get(k), f"{where}/{k}")]
    return [] if expected == got else [where]


@pytest.mark.parametrize("name", ENGINE_NAMES)
def test_engines_compute_what_they_did_before_the_interface(name, _needs_gcc):
    recorded = json.loads(FINGERPRINTS.read_text())
    if recorded["machine"] != _machine():
        pytest.skip("the fingerprints were recorded on another kind of CPU (-march=native, glibc's libm)")
    expected = recorded["engines"][name]
    got = fingerprint(name)
    assert differing(expected, got) == []
    planted = json.loads(json.dumps(got))  # negative control: one last bit of r_max changed is seen
    planted["run"]["r_max"] = [float.hex(np.nextafter(float.fromhex(planted["run"]["r_max"][0]), np.inf))]
    assert differing(expected, planted) == ["/run/r_max"]
