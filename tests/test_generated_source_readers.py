"""No code of the package (nor the benchmarks) reads generated source text (issue 33 item 2): what the
analysis and the benchmarks need of a generated model is emitted as data (the module's self-description,
program.json, auto/stages.json), so a template may change how the code is written without breaking a
reader that parsed it.

A reader, as searched here (statically, every .py file of adbgen/ and of the benchmarks' folder wherever
it lives):

- ``inspect.getsource`` (and ``getsourcelines``, ``getsourcefile``): a module's source as text;
- ``ast.parse`` of text read from a file or from ``getsource``;
- ``read_text`` / ``open`` (text mode) of a generated source file: a model's ``<name>.c``, ``.h``,
  ``__init__.py``, or of a path held in a variable assigned such a name;
- a regular expression (``re.search``, ``findall``, ``match``, ``finditer``, ``fullmatch``) over text read
  from a generated C file or an AUTO constants file ``c.<model>``.

Hashing a file's bytes (the engines' cache keys), copying the AUTO files and handing the constants file
to AUTO-07p (with KEY = value overrides, as AUTO's own ``@r`` does) are not reading it.
"""

from __future__ import annotations

import re
from pathlib import Path

import adbgen

ROOT = Path(adbgen.__file__).resolve().parent.parent
# the benchmarks: the top-level folder of the checkout since issue 33 item 6 ("bench": a checkout of before)
BENCH_FOLDERS = ("bench", "benchmarks")

# a generated source file's name in a path expression: a model's f"{name}.c", f"{name}_taylor.c", ".h", ...,
# its "__init__.py"; and its AUTO constants file f"c.{name}" (handed to AUTO, searched by no one)
_SOURCE_NAME = re.compile(r"""\}(\.c|\.h|_taylor\.c|_cvode\.c|_lanes\.h)["')]|__init__\.py["']""")
_CONSTANTS_NAME = re.compile(r"""f["']c\.\{""")
_READ = re.compile(r"\.read_text\(|(?<![\w.])open\((?![^)]*['\"]r?b['\"])")
_REGEX = re.compile(r"\bre\.(search|findall|match|finditer|fullmatch)\(")
_ASSIGN = re.compile(r"^\s*(\w+(?:\s*,\s*\w+)*)\s*=(?!=)\s*(.*)$")


def python_files() -> list[Path]:
    files = sorted((ROOT / "adbgen").rglob("*.py"))
    for name in BENCH_FOLDERS:
        folder = ROOT / name
        if folder.is_dir():
            files += sorted(folder.rglob("*.py"))
    return [f for f in files if "__pycache__" not in f.parts]


def readers(path: Path, text: str | None = None) -> list[str]:
    """`path:line: what` for every reader of generated source text in one file (see the module docstring)."""
    text = path.read_text() if text is None else text
    lines = text.splitlines()
    found = []
    source_vars = set()  # variables holding a generated source file's path
    constants_vars = set()  # variables holding an AUTO constants file's path
    read_vars = set()  # variables holding text read from one
    for k, line in enumerate(lines, start=1):
        code = line.split("#", 1)[0]
        where = f"{path.name}:{k}"
        if re.search(r"\binspect\.getsource(lines|file)?\(|\bgetsource\(", code):
            found.append(f"{where}: source of a module read as text (inspect.getsource)")
        if "ast.parse(" in code and re.search(r"read_text|getsource|source\b", code):
            found.append(f"{where}: ast.parse of source text")
        names_source = bool(_SOURCE_NAME.search(code)) or any(re.search(rf"\b{v}\b", code) for v in source_vars)
        names_constants = bool(_CONSTANTS_NAME.search(code)) or any(re.search(rf"\b{v}\b", code) for v in constants_vars)
        m = _ASSIGN.match(code)
        targets = [v.strip() for v in m.group(1).split(",")] if m else []
        if m and not _READ.search(m.group(2)):
            # (a tuple assignment: each name with its own value)
            values = m.group(2).split(",") if len(targets) > 1 else [m.group(2)]
            for name, value in zip(targets, values if len(values) == len(targets) else [m.group(2)] * len(targets)):
                if _SOURCE_NAME.search(value):
                    source_vars.add(name)
                if _CONSTANTS_NAME.search(value):
                    constants_vars.add(name)
        if (names_source or names_constants) and _READ.search(code):
            if names_source:
                found.append(f"{where}: a generated source file read as text")
            read_vars.update(targets)
        if _REGEX.search(code) and (names_source or names_constants
                                    or any(re.search(rf"\b{v}\b", code) for v in read_vars)):
            found.append(f"{where}: a regular expression over a generated file's text")
    return found


def test_no_reader_of_generated_source_text():
    found = [r for f in python_files() for r in readers(f)]
    assert found == []


def test_the_search_covers_the_package_and_the_benchmarks():
    files = python_files()
    assert any(f.name == "steady.py" for f in files) and any(f.name == "peers.py" for f in files)
    assert len(files) > 100


# the readers this issue removed, as they were (negative controls)
_PEERS_BEFORE = '''
def generated_program(module):
    source = textwrap.dedent(inspect.getsource(module.rhs_inplace.py_func))
    fn = ast.parse(source).body[0]
'''
_STAGES_BEFORE = '''
def stages(model):
    folder = model.folder / "auto"
    cfile, source = folder / f"c.{model.name}", folder / f"{model.name}.c"
    text = cfile.read_text()
    icp = [int(v) for v in re.findall(r"-?\\d+", _constants(text, "ICP") or "")]
    c = source.read_text()
    block = re.search(r"start\\[NSTATES\\]\\s*=\\s*\\{([^}]*)\\}", c)
'''
_STOP_BEFORE = '''
def default_stop(model, name, start):
    path = model.folder / "auto" / f"c.{model.name}"
    text = path.read_text()
    ds = re.search(r"\\bDS\\s*=\\s*([-+0-9.eE]+)", text)
'''
_PINNED_BEFORE = '''
def _pinned_model(model):
    return "SIGMA" in (model.folder / "auto" / f"{model.name}.c").read_text()
'''


def test_the_removed_readers_are_found():
    """Negative control: each reader this issue replaced by emitted data is found, in a planted file."""
    def kinds(text):
        return [r.split(": ", 1)[1] for r in readers(Path("planted.py"), text)]

    assert kinds(_PEERS_BEFORE) == ["source of a module read as text (inspect.getsource)", "ast.parse of source text"]
    assert kinds(_STAGES_BEFORE) == ["a regular expression over a generated file's text",
                                     "a generated source file read as text",
                                     "a regular expression over a generated file's text"]
    assert kinds(_STOP_BEFORE) == ["a regular expression over a generated file's text"]
    assert kinds(_PINNED_BEFORE) == ["a generated source file read as text"]


def test_data_files_and_bytes_are_not_readers():
    """What is allowed stays allowed: the emitted data, AUTO's output files, hashing bytes, user expressions."""
    allowed = '''
data = json.loads((model.folder / "auto" / "stages.json").read_text())
program = json.loads((Path(module.__file__).parent / "program.json").read_text())
rows = re.findall(r"Multiplier", Path(path).read_text())
h.update((folder / f"{name}.c").read_bytes())
with open(folder / f"{name}.c", "rb") as fh:
    pass
value = ev(ast.parse(text, mode="eval"))
base = (self.dir / f"c.{self.name}").read_text()
text = set_constants(base, NMX=100)
sundials = Path("/usr/include/sundials/sundials_config.h").read_text()
'''
    assert readers(Path("allowed.py"), allowed) == []
