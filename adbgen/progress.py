"""Progress on stderr for any step that can take more than about two seconds (issue 24 item 6).

    with progress.bar(total, "scan omega", enabled) as update:   update(done) as the work advances
    with progress.activity("integrating", enabled) as note:      elapsed time while a call runs;
                                                                 note("text") changes the line

tqdm, on stderr, shown only after DELAY seconds (a quick command prints nothing) and only when
stderr is a terminal or ADBGEN_PROGRESS=1 (tests, logs that want it); commands turn it off with
--quiet and under --json.  The bar is cleared when the step ends, so the command's own output
stays as it was.
"""

from __future__ import annotations

import contextlib
import os
import sys
import threading
import time

DELAY = 2.0  # seconds before a bar appears
FORCE = "ADBGEN_PROGRESS"


def wanted(quiet: bool = False, json: bool = False) -> bool:
    """Whether a command shows progress: not with --quiet or --json, and only to a terminal (or
    with ADBGEN_PROGRESS=1)."""
    if quiet or json:
        return False
    if os.environ.get(FORCE, "") not in ("", "0"):
        return True
    return bool(getattr(sys.stderr, "isatty", lambda: False)())


def _delay() -> float:
    return 0.0 if os.environ.get(FORCE, "") not in ("", "0") else DELAY


def _tqdm(**kw):
    from tqdm import tqdm

    return tqdm(file=sys.stderr, leave=False, dynamic_ncols=True, **kw)


@contextlib.contextmanager
def bar(total: float, desc: str, enabled: bool = True, unit: str = ""):
    """A bar over `total` (any unit), drawn from DELAY seconds on; the yielded function takes the
    amount done so far."""
    if not enabled:
        yield lambda done: None
        return
    start, state = time.monotonic(), {"done": 0.0, "bar": None}

    def update(done: float) -> None:
        done = min(max(float(done), 0.0), float(total))
        if state["bar"] is None:
            if time.monotonic() - start < _delay():
                state["done"] = max(state["done"], done)
                return
            state["bar"] = _tqdm(total=float(total), desc=desc, unit=unit or "it",
                                 bar_format="{desc}: {percentage:3.0f}%|{bar}| {elapsed}<{remaining}")
            state["bar"].start_t -= time.monotonic() - start  # elapsed counts from the step's start
            state["bar"].update(state["done"])
        if done > state["done"]:
            state["bar"].update(done - state["done"])
            state["done"] = done
    try:
        yield update
    finally:
        if state["bar"] is not None:
            state["bar"].close()


@contextlib.contextmanager
def activity(desc: str, enabled: bool = True):
    """Elapsed time while a long call runs, from DELAY seconds on (it need not report anything: a
    thread refreshes the line, which works across a C call that released the GIL); the yielded
    function replaces the text."""
    if not enabled:
        yield lambda text: None
        return
    stop = threading.Event()
    state = {"text": desc, "bar": None}
    lock = threading.Lock()

    def tick():
        if stop.wait(_delay()):
            return
        with lock:
            state["bar"] = _tqdm(total=None, desc=state["text"], bar_format="{desc} {elapsed}")
            state["bar"].start_t -= _delay()
        while not stop.wait(0.5):
            with lock:
                state["bar"].set_description_str(state["text"], refresh=False)
                state["bar"].refresh()

    def note(text: str) -> None:
        state["text"] = str(text)[:100]
    thread = threading.Thread(target=tick, daemon=True)
    thread.start()
    try:
        yield note
    finally:
        stop.set()
        thread.join()
        if state["bar"] is not None:
            state["bar"].close()
