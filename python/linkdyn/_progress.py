"""Progress of a sweep (``Model.bifurcation(progress=...)``) and of a continuation
(``Model.continuation(progress=...)``).

For a sweep the compiled core calls ``update(done)`` from the calling thread, between points,
holding the GIL only for that call (the points run on Rust threads without it); for a
continuation, whose number of points is not known ahead, ``point(p)`` with each point as it
joins a branch. ``close()`` comes at the end, also after an error or an interrupt.
"""

import sys
import time
from typing import Any, Callable


class _Silent:
    def update(self, done: int) -> None:
        pass

    def close(self) -> None:
        pass


class _Callback:
    """A user's ``progress(done, total)``."""

    def __init__(self, f: Callable[[int, int], Any], total: int) -> None:
        self.f, self.total = f, total

    def update(self, done: int) -> None:
        self.f(done, self.total)

    def close(self) -> None:
        pass


class _Tqdm:
    def __init__(self, bar: Any) -> None:
        self.bar, self.done = bar, 0

    def update(self, done: int) -> None:
        self.bar.update(done - self.done)
        self.done = done

    def close(self) -> None:
        self.bar.close()


class _StderrLine:
    """One line on stderr, redrawn in place on a terminal (at most 10 times a second), else a
    new line at most every 10 s, and always a last one; ``_text()`` says what it shows."""

    def __init__(self, description: str) -> None:
        self.description = description
        self.started = time.monotonic()
        self.shown = 0.0
        self.terminal = hasattr(sys.stderr, "isatty") and sys.stderr.isatty()

    def _text(self) -> str:
        raise NotImplementedError

    def _show(self) -> None:
        now = time.monotonic()
        if now - self.shown < (0.1 if self.terminal else 10.0):
            return
        self.shown = now
        if self.terminal:
            sys.stderr.write("\r" + self._text() + "\x1b[K")
        else:
            sys.stderr.write(self._text() + "\n")
        sys.stderr.flush()

    def close(self) -> None:
        sys.stderr.write(("\r" if self.terminal else "") + self._text() + "\n")
        sys.stderr.flush()


class _Line(_StderrLine):
    """A sweep without tqdm: points done of the total, the time so far and left."""

    def __init__(self, total: int, description: str) -> None:
        super().__init__(description)
        self.total = total
        self.done = 0

    def _text(self) -> str:
        elapsed = time.monotonic() - self.started
        text = f"{self.description}: {self.done}/{self.total} points, {elapsed:.0f} s"
        if 0 < self.done < self.total:
            text += f", ~{elapsed * (self.total - self.done) / self.done:.0f} s left"
        return text

    def update(self, done: int) -> None:
        self.done = done
        self._show()


def reporter(progress: Any, total: int, description: str) -> Any:
    """The progress display for ``progress=``: ``True`` a tqdm bar (a line on stderr without
    tqdm), ``False`` or ``None`` nothing, a callable ``progress(done, total)`` called after each
    point."""
    if progress is None or progress is False:
        return _Silent()
    if progress is True:
        try:
            from tqdm.auto import tqdm
        except ImportError:
            return _Line(total, description)
        return _Tqdm(tqdm(total=total, desc=description, unit="point"))
    if callable(progress):
        return _Callback(progress, total)
    raise TypeError(
        "progress=: expected True, False, None or a callable progress(done, total), "
        f"got {type(progress).__name__}"
    )


class _BranchSilent:
    def point(self, p: dict) -> None:
        pass

    def close(self) -> None:
        pass


class _BranchCallback:
    """A user's ``progress(point)``."""

    def __init__(self, f: Callable[[dict], Any]) -> None:
        self.f = f

    def point(self, p: dict) -> None:
        self.f(p)

    def close(self) -> None:
        pass


class _BranchLine(_StderrLine):
    """A continuation: points so far, the time, the last point's parameter and branch."""

    def __init__(self, description: str) -> None:
        super().__init__(description)
        self.last: dict = {}

    def _text(self) -> str:
        elapsed = time.monotonic() - self.started
        p = self.last
        text = f"{self.description}: {p.get('points', 0)} points, {elapsed:.0f} s"
        if p:
            text += f", last at {p['parameter']:.6g}"
            if p["branch"]:
                text += f" (branch {p['branch']})"
        return text

    def point(self, p: dict) -> None:
        self.last = p
        self._show()


def branch_reporter(progress: Any, description: str) -> Any:
    """The progress display of a continuation for ``progress=``: ``True`` a line on stderr,
    ``False`` or ``None`` nothing, a callable ``progress(point)`` called after each point with
    a dict (``points``, ``branch``, ``parameter``, ``stable``, ``max_abs_mu``, ``special``)."""
    if progress is None or progress is False:
        return _BranchSilent()
    if progress is True:
        return _BranchLine(description)
    if callable(progress):
        return _BranchCallback(progress)
    raise TypeError(
        "progress=: expected True, False, None or a callable progress(point), "
        f"got {type(progress).__name__}"
    )
