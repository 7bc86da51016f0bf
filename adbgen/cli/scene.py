"""`adbgen scene from-ross ROTOR --plane NODE [--plane NODE] --balls N --ball-mass M --race-radius R --out F`.

A ROSS rotor (the .toml or .json `Rotor.save` writes) -> a two-plane scene file, written only when the
rigid model is enough for the rotor over the scene's speeds (`adbgen.ross.rigidity`; docs/ross.md).
With --flexible, where rigid is not enough a flexible-rotor scene (one or two planes, the second its
[node_2]: `adbgen.ross.flexible`, docs/flexible.md) is written instead.
Exit 0 written; 1 the rigid model is not enough (one line with the numbers, nothing written); 2 bad input.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

from ..cli_types import finite, positive_int


def cmd_from_ross(args) -> int:
    from ..ross import Unbalance, from_ross
    from ..ross.rotor import RotorError
    from ..ross.scene import write

    unbalances = []
    for node, mag, phase in args.unbalance or []:
        try:
            unbalances.append(Unbalance(int(node), float(mag), float(phase)))
        except ValueError:
            raise RotorError(f"--unbalance takes NODE MAGNITUDE PHASE (kg m, rad), got {node} {mag} {phase}") from None
    if args.margin <= 1 or args.agreement <= 0:
        raise RotorError("--margin must be > 1 and --agreement > 0")
    res = from_ross(args.rotor, args.plane, args.balls, args.ball_mass, args.race_radius, speed=args.speed,
                    unbalances=unbalances, ball_damping=args.ball_damping, check=not args.no_check,
                    margin=args.margin, agreement=args.agreement)
    v = res.verdict
    line = v.line() if v is not None else "rigidity not checked (--no-check)"
    if args.json:
        print(json.dumps({"written": v is None or v.enough, "out": str(args.out), "scene": res.bridged.mapping,
                          "verdict": v.as_dict() if v is not None else None}, indent=2, sort_keys=True))
    if v is not None and not v.enough and args.flexible:
        return _write_flexible(args, unbalances, res, v, line)
    if v is not None and not v.enough:
        print(f"adbgen scene from-ross: {args.out} not written: {line}", file=sys.stderr)
        return 1
    header = (f"two-plane scene from the ROSS rotor {args.rotor} (adbgen scene from-ross), balancer planes at nodes "
              f"{', '.join(map(str, args.plane))}; lengths from the centre of mass\n{line}")
    write(res.bridged, Path(args.out), header)
    if not args.json:
        print(f"wrote {args.out}: {line}")
    return 0


def _write_flexible(args, unbalances, res, v, line) -> int:
    """Rigid is not enough: the flexible scene at the plane (two: the second its [node_2]), in the converged
    number of modes for the forward critical speeds up to the range the verdict scanned."""
    from ..ross.flexible import flexible_scene, write
    from ..ross.rotor import RotorError, load_rotor

    if len(args.plane) > 2:
        raise RotorError("the flexible scene has one or two balancer planes: give --plane once or twice with --flexible")
    two = len(args.plane) == 2
    if len(unbalances) > 1:
        raise RotorError("the flexible scene carries one unbalance, at the "
                         + ("first balancer node (the first --plane)" if two else "balancer node"))
    mapping, conv = flexible_scene(load_rotor(args.rotor), args.plane[0], args.balls, args.ball_mass,
                                   args.race_radius, res.bridged.speed, v.scanned_to,
                                   unbalance=unbalances[0] if unbalances else None, ball_damping=args.ball_damping,
                                   modes=args.modes, tolerance=args.modal_tolerance,
                                   node_2=args.plane[1] if two else None)
    k = len(mapping["modal"]["mass"])
    modes = conv.line() if conv is not None else f"k = {k} modes (--modes)"
    if args.json:
        print(json.dumps({"flexible": {"out": str(args.out), "modes": k, "scene": mapping, "nodes": list(args.plane),
                                       "convergence": {str(j): s for j, s in conv.speeds.items()} if conv else None}},
                         indent=2, sort_keys=True))
    at = (f"balancers at nodes {args.plane[0]} and {args.plane[1]} ([node_2]), the unbalance at node {args.plane[0]}"
          if two else f"balancer at node {args.plane[0]}")
    header = (f"flexible-rotor scene from the ROSS rotor {args.rotor} (adbgen scene from-ross --flexible), "
              f"{at}\n{line}\n{modes}")
    write(mapping, Path(args.out), header)
    if not args.json:
        nodes = f", balancer nodes {args.plane[0]} and {args.plane[1]}" if two else ""
        print(f"wrote {args.out} (flexible, {k} modes{nodes}): {line}; {modes}")
    return 0


def register(sub, parser_class) -> None:
    from ..ross.rigidity import AGREEMENT, MARGIN

    p = sub.add_parser("scene", help="scene files from other tools (from-ross: a ROSS rotor)")
    s = p.add_subparsers(dest="scene_command", required=True, parser_class=parser_class)
    f = s.add_parser("from-ross", help="a ROSS rotor and its balancer planes -> a two-plane scene (if rigid is enough)")
    f.add_argument("rotor", metavar="ROTOR", help="the rotor file ROSS's Rotor.save writes (.toml or .json)")
    f.add_argument("--plane", metavar="NODE", type=int, action="append", required=True,
                   help="ROSS node of a balancer plane (once or twice)")
    f.add_argument("--balls", metavar="N", type=positive_int, required=True, help="balls in each race")
    f.add_argument("--ball-mass", metavar="M", type=finite, required=True, help="mass of one ball (kg)")
    f.add_argument("--race-radius", metavar="R", type=finite, required=True, help="radius of the races (m)")
    f.add_argument("--out", metavar="FILE", required=True, help="the scene file to write")
    f.add_argument("--speed", metavar="OMEGA", type=finite, default=None,
                   help="operating speed (rad/s): the bearings' coefficients and the scene's spin (default: the "
                        "rotor's rated_w, else 1.5 x the rigid model's highest critical speed)")
    f.add_argument("--unbalance", nargs=3, metavar=("NODE", "MAGNITUDE", "PHASE"), action="append",
                   help="a point unbalance as ROSS takes it (kg m, rad); repeat for more")
    f.add_argument("--ball-damping", metavar="C_B", type=finite, default=None,
                   help="race damping of each ball (N m s/rad; default m R^2 x 1 1/s, the thesis' default ratio)")
    f.add_argument("--margin", type=finite, default=MARGIN,
                   help=f"first bending critical at least this times the top speed (default {MARGIN:g})")
    f.add_argument("--agreement", type=finite, default=AGREEMENT,
                   help=f"rigid and ROSS critical speeds within this relative difference (default {AGREEMENT:g})")
    f.add_argument("--flexible", action="store_true",
                   help="where rigid is not enough, write the flexible-rotor scene instead (one or two planes; "
                        "docs/flexible.md)")
    f.add_argument("--modes", metavar="K", type=positive_int, default=None,
                   help="with --flexible: K modes instead of the fewest whose forward critical speeds up to the "
                        "checked range are within --modal-tolerance of every larger K's")
    f.add_argument("--modal-tolerance", metavar="TOL", type=finite, default=1e-3,
                   help="with --flexible: relative tolerance of modal convergence (default 1e-3)")
    f.add_argument("--no-check", action="store_true", help="write without comparing with ROSS's Campbell diagram")
    f.add_argument("--json", action="store_true", help="print the scene and the verdict as JSON")
    f.set_defaults(fn=cmd_from_ross)
