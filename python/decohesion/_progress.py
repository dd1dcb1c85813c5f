"""Progress of ``Simulation.run(progress=True)``: a tqdm bar when tqdm is installed (a widget in
a notebook with ipywidgets, text in a terminal), otherwise a plain line on stderr, rewritten in
place on a terminal or in a notebook and printed every 10 % of the run elsewhere (a log file).

The solver calls ``update`` about every 0.1 s of wall time (with the GIL taken for that moment)
and ``close`` at the end, whatever the outcome.
"""

from __future__ import annotations

import math
import sys
import time


def bar(name: str, t0: float, until: float, h: float):
    """A progress display for a run of scene ``name`` from ``t0`` to ``until`` [s] at step ``h``
    (the expected step count is ⌈(until − t0)/h⌉, as the command line prints it)."""
    steps = math.ceil(max(0.0, until - t0) / h) if h > 0 else 0
    try:
        from tqdm.auto import tqdm
    except ImportError:
        return _Line(name, t0, until, steps)
    return _Tqdm(tqdm, name, t0, until, steps)


class _Tqdm:
    def __init__(self, tqdm, name, t0, until, steps):
        self.until = until
        self.bar = tqdm(
            total=until,
            initial=t0,
            desc=f"{name} (~{steps} steps)",
            bar_format="{desc}: {percentage:3.0f}%|{bar}| t = {n:.4g}/{total:.4g} s "
            "[{elapsed}<{remaining}{postfix}]",
            leave=True,
        )

    def update(self, t: float, step: int, ruptured: int, interface: int) -> None:
        self.bar.n = min(t, self.until)
        self.bar.set_postfix_str(f"step {step}, ruptured {ruptured}/{interface}", refresh=False)
        self.bar.refresh()

    def close(self) -> None:
        self.bar.close()


class _Line:
    def __init__(self, name, t0, until, steps):
        self.name, self.t0, self.until = name, t0, until
        self.started = time.monotonic()
        out = sys.stderr
        self.in_place = bool(getattr(out, "isatty", lambda: False)()) or "ipykernel" in sys.modules
        self.next_tenth = 1
        self.last = ""
        print(f"{name}: t = {t0:.5g} s → {until:.5g} s, ~{steps} steps", file=out)

    def _fraction(self, t: float) -> float:
        span = self.until - self.t0
        return 1.0 if span <= 0 else min(1.0, max(0.0, (t - self.t0) / span))

    def update(self, t: float, step: int, ruptured: int, interface: int) -> None:
        f = self._fraction(t)
        line = (
            f"  {100 * f:3.0f} %  t = {t:.5g} s  step {step}  ruptured {ruptured}/{interface}  "
            f"{time.monotonic() - self.started:.1f} s"
        )
        if self.in_place:
            print("\r" + line, end="", file=sys.stderr, flush=True)
        elif f * 10 >= self.next_tenth:
            self.next_tenth = int(f * 10) + 1
            print(line, file=sys.stderr, flush=True)
        self.last = line

    def close(self) -> None:
        if self.in_place and self.last:
            print(file=sys.stderr, flush=True)
