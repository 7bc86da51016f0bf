"""A model printed for people and scripts: equations of motion (rows) or a first-order system (Schur form)
as text, LaTeX or JSON (`adbgen derive`, `adbgen two-plane derive`)."""

from __future__ import annotations

import json

import sympy as sp

from .first_order import FirstOrderSystem


def print_model(model, fmt: str) -> int:
    """An EquationsOfMotion (rows) or a FirstOrderSystem (Schur form) as text, LaTeX or JSON."""
    if isinstance(model, FirstOrderSystem):
        solve = model.solve
        coords = solve.eom.coordinates
        data = {"reference": model.reference, "states": list(model.state_names),
                "parameters": [p.name for p in model.parameters],
                "schur": [[str(e) for e in solve.schur.row(i)] for i in range(solve.schur.rows)],
                "schur_rhs": [str(e) for e in solve.rhs],
                "ball_accelerations": {coords[k].qdd.name: str(a) for k, a in zip(solve.leaves, solve.leaf_accel)}}
        if solve.eom.driven_law:  # a prescribed run-up: the spin and its rates are inputs in t
            data["driven"] = {sym.name: str(expr) for sym, expr in sorted(solve.eom.driven_law.items(), key=str)}
    else:
        data = {"reference": model.reference, "coordinates": [c.name for c in model.coordinates],
                "parameters": [p.name for p in model.parameters],
                "rows": {c.name: str(model.residual(k)) for k, c in enumerate(model.coordinates)}}
    if fmt == "json":
        print(json.dumps(data, indent=2))
    elif fmt == "latex" and not isinstance(model, FirstOrderSystem):
        for k, c in enumerate(model.coordinates):
            print(f"% row {c.name}\n{sp.latex(model.residual(k))} = 0\n")
    else:
        print(f"# {data['reference']}")
        for key, value in data.items():
            if key in ("rows", "ball_accelerations", "driven"):
                for name, expr in value.items():
                    print(f"{name}: {expr}{' = 0' if key == 'rows' else ''}")
            elif key != "reference":
                print(f"{key}: {value}")
    return 0
