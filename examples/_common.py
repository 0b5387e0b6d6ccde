"""Shared by the example scripts: where they write their files, and their
checks against the references (a failed check makes the script exit with
status 1, so that a test or a CI job notices)."""
import argparse
import os
import sys
from pathlib import Path


def output_dir(doc: str) -> Path:
    """The directory for pictures and files: ``--out DIR``, else the
    environment variable STRANDKIT_OUT, else ``out/`` in the current
    directory (created if missing)."""
    p = argparse.ArgumentParser(description=doc.strip().splitlines()[0])
    p.add_argument("--out", metavar="DIR",
                   help="directory for the output (default: $STRANDKIT_OUT, else out/ in the current directory)")
    args = p.parse_args()
    out = Path(args.out or os.environ.get("STRANDKIT_OUT") or Path.cwd() / "out")
    out.mkdir(parents=True, exist_ok=True)
    return out


class Checks:
    """Collects checks, prints each, and exits with status 1 at `finish`
    if any failed."""

    def __init__(self):
        self.failed = []

    def close(self, name: str, got: float, ref: float, *, rtol: float = 0.0, atol: float = 0.0) -> bool:
        """|got − ref| ≤ max(rtol × |ref|, atol)."""
        tol = max(rtol * abs(ref), atol)
        err = abs(got - ref)
        ok = bool(err <= tol)  # False for NaN
        self._report(name, ok, f"{got:.6g} vs {ref:.6g}, error {err:.3g} (allowed {tol:.3g})")
        return ok

    def true(self, name: str, ok: bool, detail: str = "") -> bool:
        self._report(name, bool(ok), detail)
        return bool(ok)

    def _report(self, name, ok, detail):
        print(f"check {'OK  ' if ok else 'FAIL'} {name}: {detail}")
        if not ok:
            self.failed.append(name)

    def finish(self) -> None:
        if self.failed:
            print(f"FAILED {len(self.failed)} check(s): {', '.join(self.failed)}", file=sys.stderr)
            sys.exit(1)
        print("all checks passed")
