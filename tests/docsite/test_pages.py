"""The README and the pages' sources, checked without building: the README a newcomer reads (short, its
test command the one CI runs, its links alive), and each benchmark page stating the run its committed
results record."""

from __future__ import annotations

import ast
import json
import re
import tomllib
from datetime import datetime, timezone
from pathlib import Path

from site_helpers import DOCS, ROOT

from adbgen import docsite

README = ROOT / "README.md"


def code_blocks(text: str) -> list[str]:
    return re.findall(r"^```sh\n(.*?)^```", text, flags=re.S | re.M)


def test_the_readme_is_short():
    assert len(README.read_text().splitlines()) < 250


def test_the_readme_test_command_is_the_one_ci_runs():
    ci = (ROOT / ".ci" / "run").read_text()
    ci_command = ci[ci.index("apt-get update"):].strip()
    readme = README.read_text()
    tests = readme[readme.index("Tests (this is what `.ci/run` calls"):]
    assert code_blocks(tests)[0].strip() == ci_command


def test_the_readme_main_job_is_unchanged():
    """The first command of a fresh machine, exactly as the project has always documented it."""
    assert code_blocks(README.read_text())[0] == (
        'python3 -m pip install -e . && adbgen regenerate && adbgen verify && adbgen demo \\\n'
        '  && adbgen sweep thesis_rotating_n2 --grid "phi_1=0:2*pi*15/16:16" --grid "phi_2=0:2*pi*15/16:16" \\\n'
        '       --measure attractor --t-end 2000 --out out/sweep\n')


def broken_links(page: Path) -> list[str]:
    """Relative links and images of a Markdown file whose target file does not exist."""
    text = re.sub(r"```.*?```", "", page.read_text(), flags=re.S)
    targets = re.findall(r"!?\[[^\]]*\]\(([^)\s]+)\)", text)
    return [t for t in targets if not re.match(r"[a-z]+:", t)
            and not (page.parent / t.split("#")[0]).exists()]


def test_every_relative_link_of_the_readme_exists(tmp_path):
    assert broken_links(README) == []
    assert len(re.findall(r"\]\(docs/", README.read_text())) >= 14
    bad = tmp_path / "README.md"  # negative control
    bad.write_text("[gone](docs/no-such-page.md) ![x](docs/none.png) [web](https://example.org)\n")
    assert broken_links(bad) == ["docs/no-such-page.md", "docs/none.png"]


def utc_minutes(stamp: str) -> str:
    return datetime.fromisoformat(stamp).astimezone(timezone.utc).strftime("%Y-%m-%d %H:%M UTC")


def recorded_dates_missing(page: str, results: dict) -> list[str]:
    """The dates a benchmark's results file records that its page does not state."""
    stamps = [results[k] for k in ("date", "percall_date") if isinstance(results.get(k), str)]
    return [utc_minutes(s) for s in stamps if utc_minutes(s) not in page]


def test_each_benchmark_page_states_the_run_its_results_record():
    """A re-run benchmark changes its results file; its page must then be updated with it."""
    for results in sorted((ROOT / "benchmarks").glob("*.json")):
        page = DOCS / "benchmarks" / f"{results.stem}.md"
        assert page.is_file(), f"no page for {results.name}"
        text = page.read_text()
        assert "**Run record**" in text and "machine" in text and "command" in text, page.name
        assert recorded_dates_missing(text, json.loads(results.read_text())) == [], page.name
    # negative control: a results file re-run later than its page says
    simulate = json.loads((ROOT / "benchmarks" / "simulate.json").read_text())
    assert recorded_dates_missing((DOCS / "benchmarks" / "simulate.md").read_text(),
                                  {**simulate, "date": "2027-01-02T03:04:05+00:00"}) == ["2027-01-02 03:04 UTC"]


def index_rows_behind(index: str, dates: dict[str, str]) -> list[str]:
    """The benchmarks whose row in the index does not name the run their results file records."""
    rows = {m.group(1): m.group(2) for m in re.finditer(r"^\| \[(\w+)\]\(\w+\.md\) \|.*\| ([^|]*) \|$", index, re.M)}
    return sorted(name for name, stamp in dates.items() if name in rows and utc_minutes(stamp)[:-4] not in rows[name])


def test_the_benchmark_index_names_each_results_files_run():
    """The index's "run of" column goes stale when a benchmark is re-run (it did: friction and precision)."""
    index = (DOCS / "benchmarks" / "index.md").read_text()
    dates = {p.stem: d for p in (ROOT / "benchmarks").glob("*.json")
             if isinstance(d := json.loads(p.read_text()).get("date"), str)}
    assert dates and index_rows_behind(index, dates) == []
    # negative control: a re-run the index does not know of
    assert index_rows_behind(index, {**dates, "precision": "2027-01-02T03:04:05+00:00"}) == ["precision"]


def test_every_benchmark_chart_is_on_a_page():
    sources = "\n".join(p.read_text() for p in DOCS.rglob("*.md"))
    charts = sorted(p.name for p in (ROOT / "benchmarks").glob("*.png"))
    assert charts and [c for c in charts if f"benchmarks/{c})" not in sources] == []


def test_the_docs_extra_provides_what_the_build_imports():
    extra = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["optional-dependencies"]["docs"]
    names = {re.split(r"[<>=!~\[ ]", req, maxsplit=1)[0].lower() for req in extra}
    assert set(docsite.REQUIRED.values()) <= names
    assert "docs" in (ROOT / ".ci" / "run").read_text().split("pip install -e '.[")[1].split("]")[0].split(",")


def test_the_readme_python_example_runs():
    """The tour's Python block, as printed, in a fresh interpreter (numpy, SciPy, the generated model)."""
    import subprocess
    import sys

    from site_helpers import env

    [block] = re.findall(r"^```python\n(.*?)^```", README.read_text(), flags=re.S | re.M)
    run = subprocess.run([sys.executable, "-c", block], capture_output=True, text=True, cwd=ROOT, env=env(), timeout=300)
    assert run.returncode == 0, run.stderr
    final = ast.literal_eval(run.stdout.strip().replace("np.float64", ""))  # {'x': ..., 'y': ..., ...}
    assert abs(final["x"]) < 1e-4 and abs(final["y"]) < 1e-4  # balanced, as the comment says
