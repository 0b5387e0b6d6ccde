"""Progress bar: tqdm when installed, else a minimal stderr fallback."""
from __future__ import annotations

import sys
import time

__all__ = ["progress"]


class _Fallback:
    """Prints `desc: k/total (p%) elapsed` to stderr at most twice a second."""

    def __init__(self, iterable=None, total=None, desc=None, disable=False):
        self.iterable = iterable
        self.total = total if total is not None else (len(iterable) if hasattr(iterable, "__len__") else None)
        self.desc = desc or ""
        self.disable = disable
        self.n = 0
        self.t0 = time.perf_counter()
        self._last = 0.0

    def __iter__(self):
        for x in self.iterable:
            yield x
            self.update(1)
        self.close()

    def update(self, k=1):
        self.n += k
        now = time.perf_counter()
        if not self.disable and (now - self._last > 0.5 or self.n == self.total):
            self._last = now
            tot = f"/{self.total} ({100.0 * self.n / self.total:.0f}%)" if self.total else ""
            sys.stderr.write(f"\r{self.desc}: {self.n}{tot} {now - self.t0:.1f} s")
            sys.stderr.flush()

    def set_postfix_str(self, s):
        pass

    def close(self):
        if not self.disable and self.n:
            sys.stderr.write("\n")
            sys.stderr.flush()
        self.disable = True

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False


def progress(iterable=None, *, total=None, desc=None, enable=True):
    """A progress bar over ``iterable`` (or a manual one with ``total``)."""
    try:
        from tqdm.auto import tqdm
    except ImportError:  # tqdm is optional
        return _Fallback(iterable, total=total, desc=desc, disable=not enable)
    return tqdm(iterable, total=total, desc=desc, disable=not enable, leave=False)
