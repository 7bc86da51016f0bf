"""`matlab-ode45`: an emulation of MATLAB's ode45 at its defaults, for explaining published numbers.

The thesis integrated its transients with MATLAB's ode45 (ch. 5: "we use the Matlab routine ode45") and
states neither its tolerances nor how it read t_dec off the result.  This engine repeats what ode45 does
step by step (ode45_driver.c: Dormand-Prince 5(4), MATLAB's mixed error norm with threshold
AbsTol/RelTol, its initial step and step-size control, Refine = 4 output through ntrp45) on the generated
model's C library, and reads r_max and t_dec off the output points as a MATLAB user would (r_max the
largest r(t_i), t_dec the last output time with r(t_i) >= threshold).  With RelTol = 1e-3 and
AbsTol = 1e-6 (ode45's defaults) it reproduces the thesis' printed t_dec where the converged solution
does not (docs/reproduction.md), which shows those numbers are ode45's loose-tolerance values.

It is an emulation for that purpose, not an integrator to choose: its r_max and t_dec are read off
samples (not the continuous solution), its default tolerances are loose, and it keeps no exactness a
sweep relies on beyond the element-wise stage updates (identical balls stay together).
"""

from __future__ import annotations

from ..loading import AnalysisError
from .compiled import _Compiled, _load_cached, build

DEFAULT_RTOL = 1e-3  # MATLAB's RelTol default
DEFAULT_ATOL = 1e-6  # MATLAB's AbsTol default


class MatlabOde45Engine(_Compiled):
    """MATLAB's ode45 emulated (ode45_driver.c); r_max and t_dec on its Refine = 4 output points."""

    name = "matlab-ode45"
    description = ("emulation of MATLAB's ode45 (Dormand-Prince 5(4), MATLAB's error norm, initial step and "
                   "Refine = 4 output; t_dec read from the output points): for explaining published numbers")
    driver = "ode45_driver.c"
    libs: list[str] = []
    prefix = "adb_ode45"
    symmetric = True
    native_events = False

    def library(self, model):
        return _load_cached(str(build(model, self.driver, self.libs, self.extra(model), self.tag)))

    def run_many(self, model, P, Y0, t_end, rtol, atol, threshold, max_steps, threads=None, check_dt=0.0,
                 targets=(), measures=True):
        if targets:
            raise AnalysisError("matlab-ode45 has no early stop (a sweep's --measure attractor needs another engine)")
        return super().run_many(model, P, Y0, t_end, rtol, atol, threshold, max_steps, threads=threads,
                                measures=measures)


ENGINE = MatlabOde45Engine()
