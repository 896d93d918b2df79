"""The wheel carries the ontologies and shapes: installed in a fresh virtual environment
outside the repository, ``kitkb validate`` runs on the shipped scenarios."""

from __future__ import annotations

import subprocess
import sys
import venv
import zipfile
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parent.parent


@pytest.fixture(scope="module")
def wheel(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("wheel")
    subprocess.run(
        [sys.executable, "-m", "pip", "wheel", "--no-deps", "-q", "-w", str(out), str(REPO)],
        check=True,
    )
    (whl,) = out.glob("kitkb-*.whl")
    return whl


@pytest.mark.slow
def test_wheel_contains_ontologies_and_shapes(wheel: Path) -> None:
    names = zipfile.ZipFile(wheel).namelist()
    shipped = sorted(p.relative_to(REPO).as_posix() for d in ("ontologies", "shapes") for p in (REPO / d).rglob("*.ttl"))
    assert shipped == sorted(
        ["ontologies/kitting-domain.ttl", "ontologies/kitting.ttl", "ontologies/soap.ttl",
         "shapes/kitting-rules.ttl", "shapes/kitting-shapes.ttl"]
        + [f"ontologies/scenarios/{n}/{s}.ttl" for n in ("kit-a2b3c3d1e1", "small-kit", "two-designs")
           for s in ("init", "goal")])
    # the wheel carries exactly these (none missing, no stale extra)
    assert sorted(n for n in names if n.startswith("kb/_data/") and n.endswith(".ttl")) == \
        [f"kb/_data/{rel}" for rel in shipped]


@pytest.mark.slow
def test_wheel_in_fresh_venv_validates_shipped_scenarios(wheel: Path, tmp_path: Path) -> None:
    env_dir = tmp_path / "venv"
    venv.EnvBuilder(with_pip=True).create(env_dir)
    py = env_dir / "bin" / "python"
    subprocess.run([str(py), "-m", "pip", "install", "-q", str(wheel)], check=True, cwd=tmp_path)
    kitkb = env_dir / "bin" / "kitkb"
    done = subprocess.run([str(kitkb), "validate"], cwd=tmp_path, capture_output=True, text=True)
    assert done.returncode == 0, done.stdout + done.stderr
    assert "Traceback" not in done.stderr
    # it really read the packaged files, not the checkout
    where = subprocess.run(
        [str(py), "-c", "import kb.core.resources as r; print(r.ontologies_dir())"],
        cwd=tmp_path, capture_output=True, text=True, check=True,
    ).stdout.strip()
    assert str(env_dir) in where and "_data" in where
