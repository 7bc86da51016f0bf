"""ROSS's example rotor with two balls at its disk, run up through its first critical speeds at a constant rate
(issue 38, "what must be shown": a transient through the first bending critical; docs/flexible.md section 5).

The rotor of `through_critical` with damped bearings (cxx = cyy = 1000 N s/m: the case whose balanced state
is stable above 111 rad/s), the balancer at the disk of node 2 (two balls of 0.05 kg, race radius 0.1 m, the
unbalance 1e-4 kg m there), in K modes (the model section 5 draws and simulates for the damped rotor).  The
spin follows the flexible family's speed schedule (`core.speed_schedule` with a start speed): a ramp from
OMEGA_START to OMEGA at the constant rate RATE, then a hold at OMEGA for HOLD seconds; psi'' = RATE on the ramp
enters through Lagrange's equations (`families.flexible.model.derive`).  The balls start at phi = (1, -1) rad
(section 5's release), the rotor at rest.

The reference is the same generated model with the balls' masses and drags scaled by BALLS_ABSENT (1e-8):
each ball's own equation (divided by its mass) is unchanged, its forces on the rotor are 1e-8 of the real
balls', so the node moves as the rotor without a balancer (its unbalance only) to that relative order.

The node's displacement |Phi q| (the model's measure `node`) is reduced to its envelope: the largest value in
each window of WINDOW seconds (the node whirls at the spin frequency), drawn against the spin speed at the
window's centre.  Drawn, deterministically, by ``python3 -m adbgen.ross.run_up docs/figures`` (ROSS needed):
flexible_run_up.png / .json (the envelopes and the measured numbers; the ball angles only drawn).  It reads the
balanced state's stability boundary from flexible_stability.json in the same folder (`through_critical`).
`python3 -m adbgen.ross.run_up docs/figures MODEL_FOLDER` uses a model already generated from the run's scene.
"""

from __future__ import annotations

import json
import sys
import tempfile
from pathlib import Path

import numpy as np

from .through_critical import BALL_MASS, BALLS, NODE, RACE_RADIUS, TRANSIENT_START, UNBALANCE, envelope

BEARING_DAMPING = 1000.0  # N s/m: the damped case of section 5
K = 6  # modes: the larger of section 5's two rules for the damped rotor (critical speeds and stability)
OMEGA_START, OMEGA = 60.0, 160.0  # rad/s: the ramp's ends, around the first critical pair (91.89, 96.37 rad/s)
RATE = 0.5  # rad/s^2: the ramp's constant acceleration (200 s from 60 to 160 rad/s)
HOLD = 300.0  # s at OMEGA after the ramp: the balls' slow approach to the balanced state
WINDOW = 0.5  # s: the envelope's window (0.25 rad/s of speed on the ramp)
BALLS_ABSENT = 1e-8  # the reference's ball masses and drags, as a fraction of the real balls'
# the runs: (balls present, their drag as a multiple of the scene's D = m R^2 x the bridge's drag rate, title).
# With the scene's drag (section 5's) the balls are caught by the node's whirl at the critical pair; a race
# fluid 100 times as viscous carries them through it
RUNS = ((True, 1.0, "two balls, race drag D of section 5"), (True, 100.0, "two balls, drag 100 D"),
        (False, 1.0, "balls absent (masses x 1e-8)"))
LAST = 100.0  # s: the end of the hold over which the balls' mean speed is measured


def ramp_time() -> float:
    return (OMEGA - OMEGA_START) / RATE


def speed_at(t: np.ndarray, omega_start: float = OMEGA_START, omega: float = OMEGA, t_ramp: float | None = None):
    """The schedule's spin speed psi'(t): omega_start + (omega - omega_start) t / t_ramp on the ramp, then omega."""
    t_ramp = ramp_time() if t_ramp is None else t_ramp
    t = np.asarray(t, float)
    return np.where(t < t_ramp, omega_start + (omega - omega_start) * t / t_ramp, omega)


def scene_file(rotor, folder: Path, k: int = K, rate: float = RATE, hold: float = HOLD) -> Path:
    """The example's flexible scene in k modes with the run-up schedule, written to folder."""
    from .flexible import scene_mapping, write
    from .rotor import Unbalance

    mapping = scene_mapping(rotor, NODE, k, BALLS, BALL_MASS, RACE_RADIUS, OMEGA, Unbalance(NODE, UNBALANCE, 0.0))
    mapping["speed"] = {"law": "schedule", "omega": OMEGA, "omega_start": OMEGA_START,
                        "ramp_time": (OMEGA - OMEGA_START) / rate, "hold_time": hold}
    path = folder / f"example_run_up_k{k}.toml"
    write(mapping, path, f"ROSS's rotor_example(), bearings {BEARING_DAMPING:g} N s/m, balancer at node {NODE}, "
                         f"k = {k} modes, run-up {OMEGA_START:g} -> {OMEGA:g} rad/s at {rate:g} rad/s^2 "
                         "(adbgen.ross.run_up)")
    return path


def run(model, balls: bool = True, drag: float = 1.0, t_end: float | None = None, rtol: float = 1e-10,
        atol: float = 1e-14):
    """The run-up from TRANSIENT_START: (simulation, node displacement at every step, ball angles).  drag: the
    balls' drag D as a multiple of the scene's; balls=False: the balls' masses and drags scaled by BALLS_ABSENT
    (the rotor without a balancer)."""
    from ..analysis.simulate import simulate

    p = model.params({})
    names = list(model.param_names)
    p[names.index("D")] *= drag
    if not balls:
        for name in ("m", "D"):
            p[names.index(name)] *= BALLS_ABSENT
    t_end = ramp_time() + HOLD if t_end is None else t_end
    sim = simulate(model, p, TRANSIENT_START, t_end=t_end, rtol=rtol, atol=atol, threshold=1e-9)
    node = np.array([model.measure("node", t, y, p) for t, y in zip(sim.t, sim.y.T)])
    angles = sim.y[[model.index(a) for a in model.angles]]
    return sim, node, angles


def peak(t: np.ndarray, node: np.ndarray, t_ramp: float) -> tuple[float, float]:
    """(time, displacement) of the node's largest displacement on the ramp."""
    on = t <= t_ramp
    i = int(np.argmax(np.where(on, node, -np.inf)))
    return float(t[i]), float(node[i])


def critical_band(low: float, high: float, zeta_low: float, zeta_high: float, rate: float) -> tuple[float, float]:
    """Where a run-up's peak can lie, for a critical pair low <= high (an anisotropic rotor's unbalance excites
    both): from the lower one less its half-power half-width zeta w, to the upper one plus its half-width and
    the speed the ramp gains in that mode's time constant 1 / (zeta w) (the peak of a run-up lags the
    critical speed by about that much), rate / (zeta w)."""
    return low - zeta_low * low, high + zeta_high * high + rate / (zeta_high * high)


def _figure(record: dict, path: Path) -> None:
    from ..analysis.figure_style import angle_panel, pyplot
    from ..outputs import save_figure

    plt = pyplot()
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(8, 6.8))
    for r in record["runs"]:
        w = np.array(r["envelope_speed"])
        t = np.array(r["envelope_t"])
        ramp = t <= record["ramp_time"]
        top.semilogy(w[ramp], np.array(r["envelope_node"])[ramp], lw=1.0, label=r["title"])
    for c in record["critical_speeds"]:
        top.axvline(c["speed"], color="grey", ls="--" if c["whirl"] == "forward" else ":", lw=0.8)
        top.text(c["speed"], 0.95, f" {c['speed']:.4g} ({c['whirl'][0].upper()})", rotation=90, va="top",
                 fontsize=7, transform=top.get_xaxis_transform())
    top.axvline(record["stability_boundary"], color="C3", lw=1.0)
    top.axvspan(*record["peak_band"], color="C2", alpha=0.12, lw=0)
    top.set_xlabel("spin speed omega (rad/s) on the ramp")
    top.set_ylabel("node displacement |Phi q|, envelope (m)")
    top.set_title(f"ramp {record['omega_start']:g} -> {record['omega']:g} rad/s at {record['rate']:g} rad/s^2; green: "
                  f"where the peak may lie, red: the balanced state's stability boundary", fontsize=8)
    top.legend(fontsize=7, loc="lower left")
    for r in record["runs"]:
        bottom.semilogy(r["envelope_t"], r["envelope_node"], lw=1.0, label=r["title"])
    bottom.axvline(record["ramp_time"], color="k", lw=0.6)
    bottom.set_xlabel("t (s): the ramp, then the hold at omega")
    bottom.set_ylabel("node displacement, envelope (m)")
    inset = bottom.inset_axes([0.62, 0.55, 0.36, 0.4])
    balanced = record["runs"][1]
    angle_panel(inset, np.array(balanced["t"]), np.array(balanced["angles"]), balanced["angle_names"])
    inset.tick_params(labelsize=6)
    inset.set_ylabel("")
    inset.set_xlabel("t (s)", fontsize=6)
    inset.set_title(f"ball angles: {balanced['title']}", fontsize=7)
    fig.suptitle(f"ROSS rotor_example(), bearings {record['bearing_damping']:g} N s/m, two balls at node 2: "
                 f"run-up through the first critical speeds (k = {record['k']})", fontsize=9)
    fig.tight_layout()
    save_figure(fig, path, dpi=110)


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    if len(argv) not in (1, 2):
        print("usage: python3 -m adbgen.ross.run_up OUT_FOLDER [MODEL_FOLDER]  (a model generated from the run's "
              "scene; default: the scene cache generates it)", file=sys.stderr)
        return 2
    out = Path(argv[0])
    out.mkdir(parents=True, exist_ok=True)
    from ..analysis.loading import load_model
    from ..families.flexible.critical_speeds import crossings, damping_ratio
    from ..families.flexible.scene import FlexibleScene
    from .rotor import import_ross
    from .through_critical import damped_bearings

    # the stability boundary of the balanced state at constant speed, as `through_critical` drew it (section 5)
    chart = out / "flexible_stability.json"
    if not chart.exists():
        print(f"{chart}: missing; draw it first: python3 -m adbgen.ross.through_critical {out}", file=sys.stderr)
        return 1
    case = next(c for c in json.loads(chart.read_text())["cases"] if c["bearing_damping"] == BEARING_DAMPING)
    edge = case["boundaries"][str(K)][0]

    rotor = damped_bearings(import_ross().rotor_example(), BEARING_DAMPING)
    runs = []
    with tempfile.TemporaryDirectory() as tmp:
        path = scene_file(rotor, Path(tmp))
        scene = FlexibleScene.load(path)
        pair = crossings(scene.modal, OMEGA)[:2]  # the first critical pair (91.89 B, 96.37 F rad/s)
        zetas = [damping_ratio(scene.modal, c.speed) for c in pair]
        model = load_model(argv[1]) if len(argv) == 2 else load_model(scene=path)
        defaults = dict(zip(model.param_names, model.params({})))
        wanted = {"omega": OMEGA, "omega_start": OMEGA_START, "t_ramp": ramp_time(), "t_hold": HOLD}
        if any(defaults.get(name) != value for name, value in wanted.items()):
            print(f"{model.name}: not this run's model (its schedule {[defaults.get(n) for n in wanted]}, "
                  f"the run's {list(wanted.values())})", file=sys.stderr)
            return 1
        for balls, drag, title in RUNS:
            sim, node, angles = run(model, balls, drag)
            late = int(np.searchsorted(sim.t, sim.t_end - LAST))
            ball_speed = OMEGA + float(np.mean(angles[:, -1] - angles[:, late]) / (sim.t[-1] - sim.t[late]))
            et, en = envelope(sim.t, node, int(round(sim.t_end / WINDOW)))
            t_peak, n_peak = peak(sim.t, node, ramp_time())
            stride = max(1, len(sim.t) // 4000)
            hold = sim.t >= ramp_time()
            runs.append({"balls": balls, "drag": drag, "D": float(defaults["D"] * drag), "title": title,
                         "ball_speed_end": ball_speed, "status": sim.status, "engine": sim.engine,
                         "t_end": sim.t_end, "peak_t": t_peak, "peak_speed": float(speed_at(t_peak)), "peak_node": n_peak,
                         "node_at_ramp_end": float(node[(sim.t >= ramp_time() - WINDOW) & (sim.t <= ramp_time())].max()),
                         "node_last_window": float(node[sim.t >= sim.t_end - WINDOW].max()),
                         "node_hold_max": float(node[hold].max()),
                         "angles_end": [float(a) for a in angles[:, -1]], "angle_names": list(model.angles),
                         "envelope_t": et.tolist(), "envelope_speed": speed_at(et).tolist(), "envelope_node": en.tolist(),
                         "t": sim.t[::stride].tolist(), "angles": angles[:, ::stride].tolist()})
            print(f"{title}: peak {n_peak:.3e} m at {speed_at(t_peak):.2f} rad/s, end {runs[-1]['node_last_window']:.3e} m",
                  file=sys.stderr)
    record = {"rotor": "ross.rotor_example()", "bearing_damping": BEARING_DAMPING, "node": NODE, "balls": BALLS,
              "ball_mass": BALL_MASS, "race_radius": RACE_RADIUS, "unbalance": UNBALANCE, "k": K,
              "omega_start": OMEGA_START, "omega": OMEGA, "rate": RATE, "ramp_time": ramp_time(), "hold": HOLD,
              "window": WINDOW, "balls_absent": BALLS_ABSENT, "stability_boundary": edge,
              "critical_speeds": [{"speed": x.speed, "whirl": x.whirl} for x in pair],
              "damping_ratios": zetas, "peak_band": list(critical_band(pair[0].speed, pair[1].speed, *zetas, RATE)),
              "runs": runs}
    saved = {**record, "runs": [{k: v for k, v in r.items() if k not in ("t", "angles")} for r in runs]}
    (out / "flexible_run_up.json").write_text(json.dumps(saved, indent=1) + "\n")
    _figure(record, out / "flexible_run_up.png")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
