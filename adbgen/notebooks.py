"""The derivation notebooks of derive/: executed, rendered beside their sources, checked for staleness.

    adbgen notebooks                  execute every derive/NN_*.py (jupytext percent script) from a clean
                                      kernel and write the executed notebook beside it (NN_*.ipynb)
    adbgen notebooks --check          exit 1 naming each rendered notebook that is missing or older than
                                      its source (no execution: compares the source's SHA-256, stored
                                      in the rendered notebook's metadata, with the source)
    adbgen notebooks --run            execute without writing (what CI does through the tests)
    adbgen notebooks --only 03 ...    a subset, by number or name prefix
    adbgen notebooks --jobs N         N kernels at once (default 2: this machine's cores)

The percent scripts are the source of truth (reviewable diffs); the executed .ipynb files are for
readers (GitHub renders their LaTeX and figures).  Outputs with figures and timings are not byte-
reproducible, so staleness is decided by the source hash, never by comparing outputs; execution
counts, cell ids and kernel metadata are normalised so that re-rendering an unchanged notebook changes
as little as possible.  A failed assertion or error in any cell fails the command (exit 1, the cell named).

Also the helpers the notebooks use to show equations: `latex` (SymPy's printer with the references'
notation: dots for rates, epsilon for the eccentricity) and `show`/`compare` (rendered mathematics
next to the reference's printed form and its equation number).
"""

from __future__ import annotations

import hashlib
import os
import tempfile
import time
from pathlib import Path

from .errors import AdbgenError

KERNEL = "python3"
METADATA_KEY = "adbgen"


class NotebookError(AdbgenError):
    """A notebook failed, or derive/ is missing."""


# --- showing equations ------------------------------------------------------------------------------

_GREEK_NAMES = {"eps": r"\epsilon", "tau0": r"\tau_0", "omega_n": r"\omega_n"}


def _symbol_names(expr) -> dict:
    import sympy as sp

    names = {}
    for s in getattr(expr, "free_symbols", ()):
        name = s.name
        for suffix, accent in (("_ddot", r"\ddot"), ("_dot", r"\dot")):
            if name.endswith(suffix):
                base = name[: -len(suffix)]
                head, _, index = base.partition("_")
                core = _GREEK_NAMES.get(head, sp.latex(sp.Symbol(head)))
                names[s] = accent + "{" + core + "}" + (f"_{{{index}}}" if index else "")
                break
        else:
            if name in _GREEK_NAMES:
                names[s] = _GREEK_NAMES[name]
    return names


def latex(expr, **options) -> str:
    """SymPy's LaTeX with rates as dots (phi_1_dot -> \\dot{\\phi}_{1}) and eps as epsilon."""
    import sympy as sp

    expr = sp.sympify(expr)
    atoms = expr.atoms(sp.Symbol) if hasattr(expr, "atoms") else set()
    names = _symbol_names(sp.Tuple(*atoms)) if atoms else {}
    return sp.latex(expr, symbol_names=names, **options)


def _display(markdown: str, text: str) -> None:
    try:
        from IPython import get_ipython
        from IPython.display import Markdown, display
    except ImportError:  # pragma: no cover - run as a plain script
        print(text)
        return
    if get_ipython() is None:
        print(text)
    else:
        display(Markdown(markdown))


def show(label: str, expr, reference: str = "", lhs: str | None = None) -> None:
    """One equation, rendered: `label` [reference]: lhs = expr (or expr = 0 without lhs)."""
    body = latex(expr)
    eq = f"{lhs} = {body}" if lhs is not None else f"{body} = 0"
    ref = f" &nbsp; *{reference}*" if reference else ""
    _display(f"**{label}**{ref}\n\n$${eq}$$", f"{label} [{reference}]: {lhs + ' = ' if lhs else ''}{expr}")


def compare(label: str, derived, printed, reference: str, identical: bool = True) -> None:
    """Derived and printed side by side, then assert `identical` (exact, via is_identity) holds."""
    from .core import is_identity

    same = is_identity(derived, printed)
    verdict = "identical (exact)" if same else "differ"
    _display(f"**{label}** &nbsp; *{reference}*\n\nderived: $${latex(derived)} = 0$$\n\n"
             f"printed: $${latex(printed)} = 0$$\n\n&rarr; {verdict}",
             f"{label} [{reference}]: {verdict}")
    assert same == identical, f"{label}: derived and printed {reference} {verdict}, expected the opposite"


def check(result) -> None:
    """Show a library check (a CheckResult) as one line and assert it passed."""
    print(f"{'ok  ' if result.passed else 'FAIL'} {result.name} [{result.reference}]: {result.detail}")
    assert result.passed, f"{result.name}: {result.detail}"


# --- rendering --------------------------------------------------------------------------------------

def derive_dir() -> Path:
    folder = Path(__file__).resolve().parents[1] / "derive"
    if not folder.is_dir():
        raise NotebookError(f"no derive/ folder at {folder.parent} (the notebooks live in a source checkout)")
    return folder


def sources(only: list[str] | None = None) -> list[Path]:
    found = sorted(derive_dir().glob("[0-9][0-9]_*.py"))
    if only:
        unknown = [o for o in only if not any(p.stem.startswith(o) for p in found)]
        if unknown:
            raise NotebookError(f"no notebook named {', '.join(unknown)}; have {', '.join(p.stem for p in found)}")
        found = [p for p in found if any(p.stem.startswith(o) for o in only)]
    return found


def source_digest(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def rendered_path(source: Path) -> Path:
    return source.with_suffix(".ipynb")


def stale(paths: list[Path]) -> list[str]:
    """Sources whose rendered notebook is missing or was rendered from another version."""
    import nbformat

    out = []
    for src in paths:
        target = rendered_path(src)
        if not target.is_file():
            out.append(f"{target.name}: missing")
            continue
        stored = nbformat.read(target, as_version=4).metadata.get(METADATA_KEY, {}).get("source_sha256")
        if stored != source_digest(src):
            out.append(f"{target.name}: stale (rendered from another version of {src.name})")
    return out


def _normalise(nb, source: Path) -> None:
    """Drop what changes from run to run without meaning (timings, kernel versions); cell ids stable."""
    nb.metadata.pop("language_info", None)
    nb.metadata.pop("widgets", None)
    nb.metadata["kernelspec"] = {"name": KERNEL, "display_name": "Python 3", "language": "python"}
    nb.metadata.setdefault("jupytext", {}).pop("text_representation", None)
    nb.metadata[METADATA_KEY] = {"source": source.name, "source_sha256": source_digest(source),
                                 "rendered_by": "adbgen notebooks"}
    for k, cell in enumerate(nb.cells):
        cell["id"] = f"{source.stem[:2]}-{k:03d}"
        cell.metadata.pop("execution", None)
        for output in cell.get("outputs", []):
            output.get("metadata", {}).pop("execution", None)
        if "outputs" in cell:
            cell["outputs"] = _coalesce_streams(cell["outputs"])


def _coalesce_streams(outputs: list) -> list:
    """One stream output per run of prints: how the kernel chunks them depends on timing."""
    merged = []
    for out in outputs:
        if (out.get("output_type") == "stream" and merged and merged[-1].get("output_type") == "stream"
                and merged[-1].get("name") == out.get("name")):
            merged[-1]["text"] = "".join(merged[-1]["text"]) + "".join(out["text"])
        else:
            merged.append(out)
    return merged


def execute(source: Path, timeout: int = 600):
    """Run one percent script as a notebook from a clean kernel in derive/; the executed notebook."""
    import jupytext
    from nbclient import NotebookClient
    from nbclient.exceptions import CellExecutionError

    nb = jupytext.read(source)
    nb.metadata["kernelspec"] = {"name": KERNEL, "display_name": "Python 3", "language": "python"}
    # The kernel imports this checkout's adbgen (and generated/), as the caller does; only the kernel's
    # environment is changed, never this process's (later subprocesses must not inherit it).
    root, paths = str(source.parents[1]), [p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p]
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([root] + [p for p in paths if p != root])}
    client = NotebookClient(nb, timeout=timeout, kernel_name=KERNEL, record_timing=False,
                            resources={"metadata": {"path": str(source.parent)}})
    try:
        client.execute(env=env)
    except CellExecutionError as exc:
        first = str(exc).strip().splitlines()
        raise NotebookError(f"{source.name} failed: {_last_error_line(first)}") from None
    except (RuntimeError, OSError, TimeoutError) as exc:  # no kernel (jupyter_client's NoSuchKernel is a
        # KeyError), or it died or timed out
        raise NotebookError(f"{source.name}: the {KERNEL} kernel did not run it: {exc}") from None
    except KeyError as exc:
        raise NotebookError(f"{source.name}: no Jupyter kernel {KERNEL!r} (pip install ipykernel): {exc}") from None
    _normalise(nb, source)
    return nb


def _last_error_line(lines: list[str]) -> str:
    import re

    lines = [re.sub(r"\x1b\[[0-9;]*m", "", ln) for ln in lines]
    errors = [ln for ln in lines if "Error" in ln or "assert" in ln]
    return (errors[-1] if errors else lines[-1] if lines else "error").strip()[:300]


def write(nb, target: Path) -> None:
    import nbformat

    fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", dir=target.parent)
    os.close(fd)
    try:
        nbformat.write(nb, tmp)
        os.chmod(tmp, 0o644)  # mkstemp's 0600 is for secrets; a rendered notebook is for readers
        os.replace(tmp, target)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def run_all(paths: list[Path], timeout: int = 600, jobs: int = 2):
    """Execute each notebook (a clean kernel each, `jobs` at a time); yields (source, notebook or
    NotebookError, seconds) in the order of `paths`."""
    from concurrent.futures import ThreadPoolExecutor

    def one(src):
        t0 = time.perf_counter()
        try:
            return src, execute(src, timeout=timeout), time.perf_counter() - t0
        except NotebookError as exc:
            return src, exc, time.perf_counter() - t0

    with ThreadPoolExecutor(max_workers=max(1, jobs)) as pool:
        yield from pool.map(one, paths)
