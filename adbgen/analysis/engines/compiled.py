"""The compiled engines: a generated model's C library inside a C driver, called through ctypes.

Each driver (`cyrk_driver.c`, `sundials_driver.c` here; `rk_driver.c`, `rk_batch_driver.c` in rk.py,
`taylor_driver.c` in taylor.py, `ode45_driver.c` in matlab_ode45.py) is compiled once per model with gcc
into a shared library cached under ``$ADBGEN_CACHE`` (default ``~/.cache/adbgen``), keyed by the driver,
the model's C source and the flags; later runs only load it (milliseconds).  Every driver exports the one
C interface of adb_engine.h, called through its typed mirror (c_interface.py).  ctypes releases the GIL
for the call, and a batch runs on OpenMP threads inside the library: no Python per step, per evaluation
or per trajectory.  (The default engine is `auto`, engines/auto.py.)

    cyrk-dop853, cyrk-vern8, cyrk-vern7, cyrk-rk45, cyrk-rk23
        CyRK's C++ explicit Runge-Kutta solvers (CyRK.nb.numba_c_api's C entry points)
    cvode-bdf      SUNDIALS CVODE, BDF with Newton and the generated analytic Jacobian (stiff)
    cvode-adams    SUNDIALS CVODE, Adams-Moulton with fixed-point iteration (no linear algebra)
    arkode-erk8, arkode-dp5, arkode-erk6
                   SUNDIALS ARKODE ERKStep: Fehlberg 7(8), Dormand-Prince 4(5), Verner 5(6)
"""

from __future__ import annotations

import ctypes
import hashlib
import os
import shutil
import subprocess
import tempfile
import threading
from functools import lru_cache
from pathlib import Path

import numpy as np

from ..loading import AnalysisError, cache_dir
from . import c_interface as ci

HERE = Path(__file__).resolve().parent
SUNDIALS_LIBS = ["-lsundials_arkode", "-lsundials_cvode", "-lsundials_nvecserial", "-lsundials_sunmatrixdense",
                 "-lsundials_sunlinsoldense", "-lsundials_sunnonlinsolfixedpoint"]
_CFLAGS = ["-std=gnu99", "-O2", "-fPIC", "-shared", "-fopenmp"]
# Machine independence (issue 23): no fused multiply-add the source does not write, and the elementary
# functions from SLEEF's consistent scalar path instead of glibc's per-CPU variants (fixed_libm.h).
PINNED_FLAGS = ["-ffp-contract=off", "-include", "fixed_libm.h"]
PINNED_LIBS = ["-lsleef"]
_lock = threading.Lock()


def compiler() -> str:
    cc = os.environ.get("CC") or shutil.which("gcc") or shutil.which("cc")
    if not cc:
        raise AnalysisError("no C compiler found (the compiled engines need gcc: apt-get install gcc)")
    return cc


@lru_cache(maxsize=1)
def pinned_libm() -> bool:
    """Is SLEEF (the pinned libm of fixed_libm.h) there to link against?  Without it the engines fall back
    to glibc's libm, whose results depend on the processor (`adbgen reproduce` refuses to run so)."""
    probe = "#include <stddef.h>\ndouble Sleef_cinz_sind1_u10purec(double);\n" \
            "int main(void) { return Sleef_cinz_sind1_u10purec(0.5) > 0.0 ? 0 : 1; }\n"
    with tempfile.TemporaryDirectory() as tmp:
        src = Path(tmp) / "probe.c"
        src.write_text(probe)
        try:
            proc = subprocess.run([compiler(), str(src), "-o", str(Path(tmp) / "probe"), *PINNED_LIBS],
                                  capture_output=True, text=True)
        except (OSError, AnalysisError):
            return False
        return proc.returncode == 0


def libm() -> str:
    """Which libm the compiled engines use: "sleef-cinz" (pinned) or "glibc" (machine-dependent)."""
    return "sleef-cinz" if pinned_libm() else "glibc"


def _digest(path: Path) -> bytes:
    """The SHA-256 of a file's bytes, read again only when its size or modification time changes: the key
    of every engine call (reading and hashing the driver, its headers and the model's source on each call
    cost 0.25-0.3 ms, 7 % of a 3.4 ms run in `bench rk`)."""
    st = path.stat()
    return _digest_of(str(path), st.st_mtime_ns, st.st_size)


@lru_cache(maxsize=256)
def _digest_of(path: str, mtime_ns: int, size: int) -> bytes:
    return hashlib.sha256(Path(path).read_bytes()).digest()


@lru_cache(maxsize=1)
def _headers() -> tuple[bytes, ...]:
    """The digests of the drivers' headers, read once per process: they are the installed package's files
    (listing and checking a dozen of them was most of the remaining 90 us of Python around a 16 us run)."""
    return tuple(_digest(p) for p in sorted(HERE.glob("*.h")))


def compile_cached(model, drv: Path, source: Path, flags, defines, libs, kind: str, what: str,
                   key: tuple = ()) -> Path:
    """Compile the driver `drv` (which #includes the model's generated `source`) with `flags`, `defines` and
    `libs` into a shared library under $ADBGEN_CACHE/engines, named by the model and `kind` and keyed by the
    driver, every header beside it, the model's file, the arguments and `key` (e.g. the CPU that
    -march=native compiles for).  Every compiled engine's library is made here; `what` names it in the
    one-line error of a failed build."""
    h = hashlib.sha256()
    headers = _headers()  # every header a driver may include
    for part in (_digest(drv), *headers, _digest(source), " ".join([*flags, *defines, *libs]).encode(),
                 model.name.encode(), *(str(k).encode() for k in key)):
        h.update(part)
        h.update(b"\0")
    target = cache_dir() / "engines" / f"{model.name}-{kind}-{h.hexdigest()[:16]}.so"
    if target.is_file():
        return target
    target.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(suffix=".so", dir=target.parent)
    os.close(fd)
    cmd = [compiler(), *flags, f"-I{source.parent}", f"-I{HERE}", *defines, str(drv), "-o", tmp, *libs, "-lm"]
    proc = subprocess.run(cmd, capture_output=True, text=True)
    if proc.returncode != 0:
        os.unlink(tmp)
        first = next((ln for ln in proc.stderr.splitlines() if "error" in ln), proc.stderr.strip()[:300])
        raise AnalysisError(f"building the {what} for {model.name} failed: {first}")
    os.replace(tmp, target)  # atomic: concurrent builders (sweep workers) never see half a library
    return target


def build(model, driver: str, libs: list[str], extra: tuple[str, ...] = (), tag: str = "") -> Path:
    """Compile `driver` with the model's C source into a cached shared library; returns its path.  `extra`:
    more compiler arguments (a variant of the library, named by `tag` in the cache)."""
    source = model.c_source()
    flags = _CFLAGS + (PINNED_FLAGS if pinned_libm() else []) + list(extra)
    libs = list(libs) + (PINNED_LIBS if pinned_libm() else [])
    name = model.name
    defines = [f'-DADB_MODEL_SOURCE="{source}"', f"-DADB_JAC={name}_jac", f"-DADB_NY={model.n_states}",
               f"-DADB_NP={model.n_params}"]
    if not any(e.startswith("-DADB_RHS=") for e in extra):
        defines.append(f"-DADB_RHS={name}_rhs")
    return compile_cached(model, HERE / driver, source, flags, defines, libs, f"{Path(driver).stem}{tag}",
                          f"{Path(driver).stem} engine")


class _Compiled:
    """Shared by the compiled engines: the library per model, the calls through c_interface, the outputs."""

    symmetric = True
    driver = ""
    libs: list[str] = []
    prefix = ""
    tag = ""  # a variant's name in the library cache
    method_id = 0

    def extra(self, model) -> tuple[str, ...]:
        """More compiler arguments for this engine's library of `model` (a variant: symmetrized.py)."""
        return ()

    def library(self, model):
        return _load(self, model.name, model.source_hash, str(model.folder), model)

    def _single_call(self, model, rtol, atol):
        """(library, settings fields, what was picked or None) of one run (the Taylor engine: its order's
        library and its step factor)."""
        return self.library(model), {"method": self.method_id}, None

    def _many_call(self, model, rtol, atol):
        """(library, settings fields) of a batch call."""
        lib, fields, _ = self._single_call(model, rtol, atol)
        return lib, fields

    def run(self, model, p, y0, t_end, rtol, atol, threshold, max_steps, keep_trajectory=True, samples=0):
        lib, fields, picked = self._single_call(model, rtol, atol)
        s = ci.settings(model, t_end, rtol, atol, threshold, max_steps, keep=keep_trajectory, **fields)
        out = ci.single(*ci.integrate(lib, model, y0, p, s))
        if picked is not None:
            out["picked"] = picked
        return out

    def run_many(self, model, P, Y0, t_end, rtol, atol, threshold, max_steps, threads=None, check_dt=0.0,
                 targets=(), measures=True):
        lib, fields = self._many_call(model, rtol, atol)
        s = ci.settings(model, t_end, rtol, atol, threshold, max_steps, check_dt=check_dt, targets=targets,
                        measures=measures, **fields)
        return ci.integrate_many(lib, model, P, Y0, s, threads)

    def dense_output(self, model, p, t, y, times, rtol, atol) -> np.ndarray:
        """The continuous solution of a run (its accepted steps t, y as `run` returns them) at `times`
        (increasing, within [t[0], t[-1]]), states x times: each step's own interpolant (Taylor: its
        polynomial), the one r_max and t_dec are located on.  An engine whose driver has adb_dense offers
        it as `dense`."""
        lib, fields, _ = self._single_call(model, rtol, atol)
        code, out = ci.dense(lib, model, p, t, y, times, ci.settings(model, t[-1], rtol, atol, **fields))
        if code:
            raise AnalysisError(f"{self.name} failed to integrate a step again for its dense output")
        return out


@lru_cache(maxsize=None)
def _load_cached(path: str):
    return ci.open_library(path)


def _load(engine, name, source_hash, folder, model):
    with _lock:
        lib = _load_cached(str(build(model, engine.driver, engine.libs, engine.extra(model), engine.tag)))
        if engine.prefix == "adb_cyrk" and not getattr(lib, "_adbgen_ready", False):
            lib.adb_cyrk_init.restype = ctypes.c_int
            ptrs = (ctypes.c_void_p * 9)(*_cyrk_pointers())
            lib.adb_cyrk_init(ptrs)
            lib._adbgen_ready = True
        return lib


@lru_cache(maxsize=1)
def _cyrk_pointers() -> tuple[int, ...]:
    try:
        import CyRK.nb.numba_c_api as api
    except ImportError as exc:  # a declared dependency: a broken install, said in one line
        raise AnalysisError(f"CyRK is not importable ({exc}); pip install 'CyRK>=0.20'") from None
    return (api.get_solve_func_ptr(), api.get_success_func_ptr(), api.get_status_func_ptr(),
            api.get_size_func_ptr(), api.get_t_func_ptr(), api.get_y_func_ptr(), api.get_steps_taken_func_ptr(),
            api.get_call_call_func_ptr(), api.get_free_func_ptr())


@lru_cache(maxsize=1)
def _cyrk_methods() -> dict[str, int]:
    from CyRK.cy.pyhelpers import find_ode_method_int

    return {m: find_ode_method_int(m) for m in ("DOP853", "Vern8", "Vern7", "RK45", "RK23")}


class CyRKEngine(_Compiled):
    """CyRK's C++ explicit Runge-Kutta (cyrk_driver.c)."""

    driver = "cyrk_driver.c"
    libs: list[str] = []
    prefix = "adb_cyrk"
    native_events = False

    def __init__(self, method: str):
        self.method = method
        self.name = "cyrk-" + method.lower()
        self.description = f"CyRK {method} (C++) on the generated C library; compiled, no Python per step"

    @property
    def method_id(self) -> int:
        return _cyrk_methods()[self.method]

    dense = _Compiled.dense_output

class SundialsEngine(_Compiled):
    """SUNDIALS CVODE or ARKODE ERKStep (sundials_driver.c); events by SUNDIALS' root finding."""

    driver = "sundials_driver.c"
    libs = SUNDIALS_LIBS
    prefix = "adb_sundials"
    native_events = True

    def __init__(self, name: str, method_id: int, description: str, symmetric: bool):
        self.name = name
        self.method_id = method_id
        self.description = description
        self.symmetric = symmetric

    def run(self, model, p, y0, t_end, rtol, atol, threshold, max_steps, keep_trajectory=True, samples=2001):
        """One run with `samples` states on an even grid (SUNDIALS keeps no steps: its own output points)."""
        lib = self.library(model)
        n_s = int(samples) if keep_trajectory else 0
        times = np.linspace(0.0, t_end, n_s + 1)[1:] if n_s else np.zeros(0)
        out = np.zeros((max(n_s, 1), model.n_states))
        msg = ctypes.create_string_buffer(256)
        s = ci.settings(model, t_end, rtol, atol, threshold, max_steps, method=self.method_id, sample_times=times,
                        samples=out, message=msg)
        code, _, _, y_end, res, wall = ci.integrate(lib, model, y0, p, s)
        reached = int(np.searchsorted(times, res.t_last, side="right")) if n_s else 0
        t = np.concatenate([[0.0], times[:reached]])
        y = np.vstack([np.asarray(y0, dtype=float), out[:reached]]).T
        return ci.single(code, t, y, y_end, res, wall, msg.value.decode(errors="replace"))
