"""Stick and slip as an event-driven hybrid system (issue 37, item 2): the `hybrid-dop853` engine
(hybrid_driver.c, DOP853 compiled with the model's C rhs and measures).

A model whose stick phase is modelled says so in its self-description: per ball k (1, 2, ...) the
parameters stuck_k (its mode: 1 stuck, 0 slipping) and slip_dir_k (the direction of its slip, along which
the model's friction acts: each mode's field is smooth), and the measures slip_rate_k, stick_margin_k and
stick_force_k (the switching functions, emitted from the symbolic model).  This module finds them by those
names, so it names no family.  A model whose switching functions hold accelerations with no closed form (a rotor
core its rhs solves numerically) declares them as parameters accel_<coordinate>, read by its measures only: the
driver fills them from the model's rhs before such a measure is evaluated (`measure` does the same here).  The driver sets the modes at the start (every ball at rest on the race is
decided there) and at every event, the balls that switch at once decided together from one state (`decide_set`);
the parameters' values given for stuck_k and slip_dir_k are ignored (tests/analysis/test_hybrid_modes.py).
"""

from __future__ import annotations

import ctypes
from dataclasses import dataclass

import numpy as np

from ..loading import AnalysisError
from .c_interface import D, I
from .rk import _sizes, build

# no_consistent_mode: a ball can neither stick (its margin < 0) nor slip (the decided slip decelerates at once,
# mu_r > mu_s); the driver stops there (hybrid_driver.c, HY_NO_MODE under HY_MODE_CHECK) rather than looping to max_events
STATUS = {0: "success", 1: "max_steps", 2: "max_events", 3: "step_underflow", 4: "nonfinite",
          5: "no_consistent_mode"}
MODES = {0: "stick", 1: "slip+", -1: "slip-"}


@dataclass(frozen=True)
class Switching:
    """Indices of the hybrid system's modes and switching functions in a model."""

    stuck: tuple[int, ...]  # parameter indices
    slip_dir: tuple[int, ...]
    rate_state: tuple[int, ...]  # state index of each ball's slip rate
    rate: tuple[int, ...]  # measure indices
    margin: tuple[int, ...]
    force: tuple[int, ...]
    accel_param: tuple[int, ...] = ()  # parameters accel_<coordinate> the measures read ...
    accel_state: tuple[int, ...] = ()  # ... and the state whose derivative (the rhs') fills each


def switching(model) -> Switching:
    """The model's switching balls, from its self-description; a one-line error if it has none."""
    balls = 0
    while f"stuck_{balls + 1}" in model.param_names:
        balls += 1
    measures = model.measures
    need = [f"{kind}_{k}" for k in range(1, balls + 1) for kind in ("slip_rate", "stick_margin", "stick_force")]
    if not balls or any(name not in measures for name in need):
        raise AnalysisError(f"{model.name} has no stick phase (a scene with static_friction makes one)")
    rate_state = []
    probe = np.arange(1.0, model.n_states + 1.0)
    p = model.params()
    for k in range(1, balls + 1):  # the ball's own rate: the one state whose unit increase raises the slip rate by 1
        value = model.measure(f"slip_rate_{k}", 0.0, probe, p)
        hits = [i for i in range(model.n_states)
                if model.measure(f"slip_rate_{k}", 0.0, probe + np.eye(model.n_states)[i], p) - value == 1.0]
        if len(hits) != 1:
            raise AnalysisError(f"{model.name}: slip_rate_{k} is not a ball's rate (relative to its race)")
        rate_state.append(int(hits[0]))
    index = measures.index
    accel = [(i, name.removeprefix("accel_")) for i, name in enumerate(model.param_names) if name.startswith("accel_")]
    return Switching(tuple(model.param_names.index(f"stuck_{k}") for k in range(1, balls + 1)),
                     tuple(model.param_names.index(f"slip_dir_{k}") for k in range(1, balls + 1)),
                     tuple(rate_state),
                     tuple(index(f"slip_rate_{k}") for k in range(1, balls + 1)),
                     tuple(index(f"stick_margin_{k}") for k in range(1, balls + 1)),
                     tuple(index(f"stick_force_{k}") for k in range(1, balls + 1)),
                     tuple(i for i, _ in accel), tuple(model.rate_index(model.index(c)) for _, c in accel))


def with_accelerations(model, t: float, y, p, sw: Switching | None = None) -> np.ndarray:
    """p with the model's acceleration inputs (accel_<coordinate>, if any) filled from its rhs at (t, y, p), as
    the driver fills them: the normal and stick forces of a model without a closed-form core solve are right
    only so.  `sw`: the model's `switching`, when the caller has it."""
    p = np.array(p, dtype=float)
    sw = switching(model) if sw is None else sw
    if sw.accel_param:
        f = model.module.rhs(float(t), np.asarray(y, dtype=float), p)
        p[list(sw.accel_param)] = np.asarray(f)[list(sw.accel_state)]
    return p


def measure(model, name: str, t: float, y, p) -> float:
    """A measure of a stick/slip model at (t, y, p) with its acceleration inputs filled (`with_accelerations`)."""
    return model.measure(name, t, y, with_accelerations(model, t, y, p))


@dataclass(frozen=True)
class HybridRun:
    t: np.ndarray  # the requested times reached
    y: np.ndarray  # (len(t), states)
    events: tuple[tuple[float, int, str], ...]  # (time, ball 1.., new mode: stick, slip+, slip-)
    status: str
    t_end: float
    y_end: np.ndarray
    params_end: np.ndarray  # with the modes at t_end
    steps: int

    def modes(self, n_balls: int) -> tuple[str, ...]:
        """Each ball's mode at t_end."""
        out = ["?"] * n_balls
        for _, b, mode in self.events:
            out[b - 1] = mode
        return tuple(out)


def library(model, extra: tuple[str, ...] = ()):
    """The driver compiled with the model; `extra`: more -D defines (a test plants HY_LOCATE_ITERATIONS=0 or
    HY_MODE_CHECK=0)."""
    source = model.c_source()
    defines = [f'-DADB_MODEL_SOURCE="{source.name}"', f"-DADB_RHS={model.name}_rhs",
               f"-DADB_MEASURE={model.name}_measure", *_sizes(model), *extra]
    lib = ctypes.CDLL(str(build(model, "hybrid_driver.c", source, defines, [])))
    lib.adb_hybrid_run.restype = ctypes.c_int
    lib.adb_hybrid_run.argtypes = RUN_ARGTYPES
    return lib


# adb_hybrid_run's 28 parameters as hybrid_driver.c declares them, so that a wrong argument is refused by ctypes
# (issue 33 item 1: no untyped call into a driver); the driver is outside adb_engine.h (its events change the
# model's parameters, a run it owns), so it is typed here rather than in c_interface.SIGNATURES
_L, _F, _LP = ctypes.c_long, ctypes.c_double, ctypes.POINTER(ctypes.c_long)
RUN_ARGTYPES = [D, _F, _F, D, ctypes.c_int, I, I, I, I, I, I, _F, _F, _L, D, _L, D, D, I, I, _L, _LP,
                ctypes.POINTER(ctypes.c_double), D, _LP, ctypes.c_int, I, I]


def run(model, p, y0, t0: float, t1: float, t_eval=None, rtol: float = 1e-10, atol: float = 1e-12,
        max_steps: int = 10_000_000, max_events: int = 100_000) -> HybridRun:
    """One hybrid run from (t0, y0) to t1 with parameters p (modes: set by the driver)."""
    sw = switching(model)
    if not t1 > t0:
        raise AnalysisError(f"t_end {t1} must be after t0 {t0}")
    t_eval = np.ascontiguousarray(np.linspace(t0, t1, 201) if t_eval is None else t_eval, dtype=float)
    if t_eval.ndim != 1 or np.any(np.diff(t_eval) < 0) or (len(t_eval) and (t_eval[0] < t0 or t_eval[-1] > t1)):
        raise AnalysisError("t_eval must be increasing and within [t0, t_end]")
    y0 = np.ascontiguousarray(y0, dtype=float).copy()
    p = np.ascontiguousarray(p, dtype=float).copy()
    ny = model.n_states
    Y = np.full((len(t_eval), ny), np.nan)
    ev_t = np.zeros(max_events)
    ev_b = np.zeros(max_events, dtype=np.int32)
    ev_m = np.zeros(max_events, dtype=np.int32)
    n_ev, n_steps = ctypes.c_long(0), ctypes.c_long(0)
    t_end = ctypes.c_double(0.0)
    y_end = np.zeros(ny)

    def ints(values):
        return np.ascontiguousarray(values, dtype=np.int32)

    arrays = [ints(v) for v in (sw.stuck, sw.slip_dir, sw.rate_state, sw.rate, sw.margin, sw.force)]
    accel = [ints(v if v else (0,)) for v in (sw.accel_param, sw.accel_state)]
    code = library(model).adb_hybrid_run(
        y0.ctypes.data_as(D), ctypes.c_double(t0), ctypes.c_double(t1), p.ctypes.data_as(D),
        ctypes.c_int(len(sw.stuck)), *(a.ctypes.data_as(I) for a in arrays), ctypes.c_double(rtol),
        ctypes.c_double(atol), ctypes.c_long(max_steps), t_eval.ctypes.data_as(D), ctypes.c_long(len(t_eval)),
        Y.ctypes.data_as(D), ev_t.ctypes.data_as(D), ev_b.ctypes.data_as(I), ev_m.ctypes.data_as(I),
        ctypes.c_long(max_events), ctypes.byref(n_ev), ctypes.byref(t_end), y_end.ctypes.data_as(D),
        ctypes.byref(n_steps), ctypes.c_int(len(sw.accel_param)), *(a.ctypes.data_as(I) for a in accel))
    reached = t_eval <= t_end.value
    events = tuple((float(ev_t[k]), int(ev_b[k]) + 1, MODES[int(ev_m[k])]) for k in range(n_ev.value))
    return HybridRun(t_eval[reached], Y[reached], events, STATUS.get(code, f"status {code}"), float(t_end.value),
                     y_end, p, int(n_steps.value))


def modes_along(model, p, events, times) -> list[np.ndarray]:
    """The parameters with each ball's mode (stuck_k, slip_dir_k) as the run's events set them, at each of the
    increasing `times` (slip_dir_k = 0 while stuck, as the driver sets it): the measures of a piece are those
    of its modes."""
    out, k, current = [], 0, np.array(p, float)
    for t in times:
        while k < len(events) and events[k][0] <= t:
            _, ball, mode = events[k]
            current = current.copy()
            current[model.param_names.index(f"stuck_{ball}")] = 1.0 if mode == "stick" else 0.0
            current[model.param_names.index(f"slip_dir_{ball}")] = {"stick": 0.0, "slip+": 1.0, "slip-": -1.0}[mode]
            k += 1
        out.append(current)
    return out


def gauss_nodes(ends, nodes: int, piece: float) -> tuple[np.ndarray, np.ndarray, list[int]]:
    """Gauss-Legendre quadrature over the smooth pieces between consecutive `ends` (a run's start, its events,
    its end), each cut into parts of at most `piece`: (times, weights, marks), times starting with ends[0] and
    holding every later end (weight 0) at the indices `marks`, so that cumsum(weights * f(times))[marks] is
    the integral of f from ends[0] to each end."""
    x, w = np.polynomial.legendre.leggauss(nodes)
    times, weights, marks = [float(ends[0])], [0.0], []
    for a, b in zip(ends[:-1], ends[1:]):
        edges = np.linspace(a, b, max(1, int(np.ceil((b - a) / piece))) + 1)
        for lo, hi in zip(edges[:-1], edges[1:]):
            times += list((hi + lo) / 2 + (hi - lo) / 2 * x)
            weights += list((hi - lo) / 2 * w)
        times.append(b)
        weights.append(0.0)
        marks.append(len(times) - 1)
    return np.array(times), np.array(weights), marks
