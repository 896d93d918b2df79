"""Where the NIST reference files are: ``../shared/nist`` beside the checkout (as in CI),
``$KITKB_NIST_DIR`` if set, else the workplace's ``/work/shared/nist``."""

from __future__ import annotations

import os
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent


def _nist_dir() -> Path:
    candidates = [Path(p) for p in [os.environ.get("KITKB_NIST_DIR")] if p]
    candidates += [REPO.parent / "shared" / "nist", Path("/work/shared/nist")]
    return next((c for c in candidates if c.is_dir()), candidates[0])


NIST_DIR = _nist_dir()
