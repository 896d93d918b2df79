"""Validation benchmark: kitkb's SHACL engine against plain pySHACL.

For each size (parts in the workstation) it builds the data once, then runs each engine in
a fresh subprocess (so peak memory, ``ru_maxrss``, belongs to that run alone):

* ``kitkb``: parse with pyoxigraph (``kb.shacl.load_index``, data and model), read the
  shapes with rdflib, validate with ``kb.shacl.validate_index``; median of ``--repeat``
  runs.
* ``pyshacl``: parse data and model with rdflib, ``pyshacl.validate(data, shacl_graph=shapes,
  ont_graph=model)`` with default options; one run. The same child then runs kitkb's engine
  on the same files and shapes graph and compares the result sets.

Data: by default the real thing - ``kb.scenario.write_scenario`` workstations with about 1%
injected violations, validated against ``shapes/kitting-shapes.ttl`` + ``kitting-rules.ttl``
with ``ontologies/kitting.ttl`` as model. ``--synthetic`` uses ``synthetic_kitting.py`` instead.

    .venv/bin/python benchmarks/bench_validate.py                 # 1k, 10k, 50k; pySHACL at 1k
    .venv/bin/python benchmarks/bench_validate.py --pyshacl-big   # pySHACL at 10k and 50k too
    .venv/bin/python benchmarks/bench_validate.py --sizes 10000 --pyshacl-sizes 10000 --engines pyshacl

End to end (``--e2e``, on by default): the whole ``kitkb validate INIT.ttl`` command in a
subprocess on a generated scenario (``kits=1``, seed 1, the same ~1% injected violations,
written as N-Triples in ``init.ttl`` so reports carry line numbers): wall time, CPU time
and peak memory (``ru_maxrss`` of that child, from ``os.wait4``); median of 3 runs up to
10,000 parts, one run above.

Measurements accumulate in ``benchmarks/results/validate.json`` (keyed by data set, size and
engine); each run rewrites the "## Validation" section of ``docs/benchmarks.md`` from it.

Against a baseline checkout (``--baseline DIR``, e.g. ``git worktree add /tmp/kitkb-before
REV``): the same end-to-end ``kitkb validate`` of each ``--baseline-sizes`` file by both
checkouts, taking turns (``--baseline-runs`` each, after one warm-up), with this checkout also
given a users' shapes file (``--shapes``, the cost of issue 20's new option), and the W3C SHACL
test suite (``tests/data/w3c-shacl``) counted for both checkouts and pySHACL; rewrites the
section "## SHACL conformance and users' shapes" only::

    .venv/bin/python benchmarks/bench_validate.py --baseline /tmp/kitkb-before --baseline-sizes 10000
"""

from __future__ import annotations

import argparse
import datetime as dt
import json
import os
import platform
import random
import re
import resource
import statistics
import subprocess
import sys
import time
from collections import Counter
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(HERE))

RESULTS = HERE / "results" / "validate.json"
DOC = ROOT / "docs" / "benchmarks.md"
KTW = "https://w3id.org/kitkb/kitting#"
RDF_TYPE = "<http://www.w3.org/1999/02/22-rdf-syntax-ns#type>"
XSD = "http://www.w3.org/2001/XMLSchema#"


# ---------------------------------------------------------------- data sets


def _k(local: str) -> str:
    return f"<{KTW}{local}>"


def inject(nt: str, rate: float, seed: int) -> tuple[str, Counter]:
    """Inject violations into N-Triples text of a generated workstation (about ``rate`` of the parts).

    Kinds, in turn: missing SKU (sh:minCount), extra property (sh:closed), wrong datatype of the
    serial number, SKU pointing at a pose (sh:class), second serial number (sh:maxCount), x axis
    not of unit length (SPARQL rule), zero SKU weight (sh:minExclusive). The workstation's length
    unit is set outside its sh:in list once.
    """
    rnd = random.Random(seed)
    lines = nt.splitlines()
    spo: dict[str, dict[str, list[int]]] = {}
    for i, line in enumerate(lines):
        s, p, _ = line.split(" ", 2)
        spo.setdefault(s, {}).setdefault(p, []).append(i)
    obj = lambda i: lines[i].split(" ", 2)[2][:-2]  # noqa: E731
    parts = sorted(s for s, preds in spo.items() for i in preds.get(RDF_TYPE, ()) if obj(i) == _k("Part"))
    chosen = rnd.sample(parts, max(1, round(len(parts) * rate))) if parts else []
    kinds = ("missing", "closed", "datatype", "class", "maxcount", "axis", "weight")
    done: Counter = Counter()
    drop: set[int] = set()
    extra: list[str] = []
    for n, part in enumerate(sorted(chosen)):
        kind = kinds[n % len(kinds)]
        preds = spo[part]
        if kind == "missing" and _k("hasSkuObject_Sku") in preds:
            drop.update(preds[_k("hasSkuObject_Sku")])
        elif kind == "closed":
            extra.append(f'{part} {_k("hasPart_Colour")} "red" .')
        elif kind == "datatype" and _k("hasPart_SerialNumber") in preds:
            i = preds[_k("hasPart_SerialNumber")][0]
            lines[i] = f'{part} {_k("hasPart_SerialNumber")} "{n}"^^<{XSD}integer> .'
        elif kind == "class" and _k("hasSkuObject_Sku") in preds:
            i = preds[_k("hasSkuObject_Sku")][0]
            pose = obj(preds[_k("hasSolidObject_PrimaryLocation")][0])
            lines[i] = f"{part} {_k('hasSkuObject_Sku')} {pose} ."
        elif kind == "maxcount":
            extra.append(f'{part} {_k("hasPart_SerialNumber")} "dup_{n}"^^<{XSD}NMTOKEN> .')
        elif kind == "axis":
            pose = obj(spo[part][_k("hasSolidObject_PrimaryLocation")][0])
            x = obj(spo[pose][_k("hasPoseLocation_XAxis")][0])
            i = spo[x][_k("hasVector_J")][0]
            lines[i] = f'{x} {_k("hasVector_J")} "0.5"^^<{XSD}decimal> .'
        elif kind == "weight":
            sku = obj(spo[part][_k("hasSkuObject_Sku")][0])
            if _k("hasStockKeepingUnit_Weight") in spo.get(sku, {}):
                i = spo[sku][_k("hasStockKeepingUnit_Weight")][0]
                lines[i] = f'{sku} {_k("hasStockKeepingUnit_Weight")} "0.0"^^<{XSD}decimal> .'
        else:
            continue
        done[kind] += 1
    for s, preds in spo.items():
        if _k("hasKittingWorkstation_LengthUnit") in preds:
            i = preds[_k("hasKittingWorkstation_LengthUnit")][0]
            lines[i] = f'{s} {_k("hasKittingWorkstation_LengthUnit")} "furlong" .'
            done["in"] += 1
            break
    kept = [line for i, line in enumerate(lines) if i not in drop]
    return "\n".join(kept + extra) + "\n", done


def make_real(parts: int, out: Path, seed: int = 1, rate: float = 0.01) -> dict:
    import pyoxigraph as ox

    from kb.core.resources import ontology_path, shapes_path
    from kb.scenario import write_scenario

    init, _goal = write_scenario(out / "scenario", parts=parts, kits=max(1, parts // 10), seed=seed)
    nt = ox.serialize(ox.parse(path=str(init), format=ox.RdfFormat.TURTLE), format=ox.RdfFormat.N_TRIPLES)
    text, kinds = inject(nt.decode(), rate, seed)
    data = out / "data.nt"
    data.write_text(text)
    return {
        "data": str(data),
        "model": str(ontology_path("kitting.ttl")),
        "shapes": [str(shapes_path("kitting-shapes.ttl")), str(shapes_path("kitting-rules.ttl"))],
        "injected": dict(kinds),
        "triples": text.count("\n"),
    }


def make_synthetic(parts: int, out: Path, seed: int = 1) -> dict:
    import synthetic_kitting

    paths = synthetic_kitting.write_synthetic(out, parts, seed=seed)
    _, injected = synthetic_kitting.data_text(parts, seed)
    return {
        "data": str(paths["data"]),
        "model": str(paths["model"]),
        "shapes": [str(paths["shapes"])],
        "injected": {"total": injected},
        "triples": None,
    }


def make_e2e(parts: int, out: Path, seed: int = 1, rate: float = 0.01) -> dict:
    """A generated scenario (one kit) with injected violations, as ``out/init.ttl``."""
    import pyoxigraph as ox

    from kb.scenario import write_scenario

    init, _goal = write_scenario(out / "scenario", parts=parts, kits=1, seed=seed)
    nt = ox.serialize(ox.parse(path=str(init), format=ox.RdfFormat.TURTLE), format=ox.RdfFormat.N_TRIPLES)
    text, kinds = inject(nt.decode(), rate, seed)
    data = out / "init.ttl"
    data.write_text(text)
    return {"data": str(data), "injected": dict(kinds), "triples": text.count("\n"),
            "bytes": data.stat().st_size}


def kitkb_command() -> list[str]:
    """The ``kitkb`` console command of this interpreter's environment (else ``python -m kb.cli``)."""
    script = Path(sys.executable).parent / "kitkb"
    return [str(script)] if script.exists() else [sys.executable, "-m", "kb.cli"]


_LAUNCHER = """
import json, os, subprocess, sys, tempfile, time
cmd, cwd = json.loads(sys.argv[1]), sys.argv[2]
with tempfile.TemporaryFile("w+") as out:
    t = time.perf_counter()
    proc = subprocess.Popen(cmd, stdout=out, stderr=subprocess.PIPE, cwd=cwd, text=True)
    _, status, usage = os.wait4(proc.pid, 0)
    wall = time.perf_counter() - t
    err = proc.stderr.read() if proc.stderr else ""
    out.seek(0)
    print(json.dumps({"wall_s": wall, "cpu_s": usage.ru_utime + usage.ru_stime, "maxrss_kb": usage.ru_maxrss,
                      "code": os.waitstatus_to_exitcode(status), "stdout": out.read(), "stderr": err[-3000:]}))
"""


def run_e2e(data: str, command: list[str] | None = None, extra: list[str] | None = None) -> dict:
    """Run ``kitkb validate DATA`` once: wall and CPU seconds, peak MB, exit code, report lines.

    ``command``: how to start kitkb (default :func:`kitkb_command`; :func:`tree_command` for a
    checkout); ``extra``: more arguments. The command is started by a small launcher process:
    a process forked from this one (big after generating the data) would inherit its peak RSS
    (Linux keeps ``ru_maxrss`` across fork and exec), and the peak memory would be this
    benchmark's, not kitkb's.
    """
    cmd = [*(command or kitkb_command()), "validate", data, *(extra or [])]
    done = subprocess.run([sys.executable, "-c", _LAUNCHER, json.dumps(cmd), str(ROOT)],
                          capture_output=True, text=True, check=True)
    got = json.loads(done.stdout)
    if got["code"] not in (0, 1):
        raise RuntimeError(f"kitkb validate failed ({got['code']}):\n{got['stderr']}")
    lines = got["stdout"].splitlines()
    return {"wall_s": got["wall_s"], "cpu_s": got["cpu_s"], "maxrss_mb": got["maxrss_kb"] / 1024,
            "exit": got["code"], "diagnostics": max(0, len(lines) - 1),
            "with_line": sum(1 for line in lines[:-1] if re.match(r"^[^:]+:\d+: ", line)),
            "summary": lines[-1] if lines else "", "report": got["stdout"]}


_TREE_RUN = "import sys; sys.path.insert(0, sys.argv.pop(1)); from kb.cli import run; run()"


def tree_command(tree: Path) -> list[str]:
    """kitkb of checkout ``tree`` (its ``kb`` first on the path; this interpreter and packages),
    started as the console script is (``kb.cli.run``)."""
    return [sys.executable, "-c", _TREE_RUN, str(tree)]


# ---------------------------------------------------------------- child processes


def _shapes_graph(files: list[str]):
    from rdflib import Graph

    g = Graph()
    for f in files:
        g.parse(f)
    return g


def _norm_key(k: tuple) -> tuple:
    from rdflib import BNode

    focus, comp, shape, path, value = k
    return (
        "_:" if isinstance(focus, BNode) else focus,
        comp,
        shape,
        path,
        "_:" if isinstance(value, BNode) else value,
    )


def child_kitkb(spec: dict) -> dict:
    from kb.shacl import load_index, validate_index

    t0 = time.perf_counter()
    index = load_index([spec["data"], spec["model"]])
    t1 = time.perf_counter()
    shapes = _shapes_graph(spec["shapes"])
    t2 = time.perf_counter()
    run = validate_index(index, shapes, sources=[spec["data"], spec["model"]])
    t3 = time.perf_counter()
    return {
        "parse_s": t1 - t0,
        "shapes_s": t2 - t1,
        "validate_s": t3 - t2,
        "total_s": t3 - t0,
        "results": len(run.results),
        "triples": index.triples,
        "fallback_shapes": len(run.fallback),
        "by_component": dict(Counter(str(r.component).split("#")[1] for r in run.results)),
    }


def child_pyshacl(spec: dict) -> dict:
    import logging

    import pyshacl
    from rdflib import Graph

    from kb.shacl.fallback import results_from_report
    from kb.shacl import validate_files

    logging.getLogger("rdflib.term").setLevel(logging.CRITICAL)
    t0 = time.perf_counter()
    data = Graph().parse(spec["data"])
    model = Graph().parse(spec["model"])
    t1 = time.perf_counter()
    shapes = _shapes_graph(spec["shapes"])
    t2 = time.perf_counter()
    _, report, _ = pyshacl.validate(data, shacl_graph=shapes, ont_graph=model, allow_warnings=True)
    t3 = time.perf_counter()
    theirs = Counter(_norm_key(r.key()) for r in results_from_report(report))
    usage = resource.getrusage(resource.RUSAGE_SELF)
    out = {"parse_s": t1 - t0, "shapes_s": t2 - t1, "validate_s": t3 - t2, "total_s": t3 - t0,
           "results": sum(theirs.values()), "triples": len(data) + len(model),
           "cpu_s": usage.ru_utime + usage.ru_stime}  # before the comparison run below
    if spec.get("compare"):
        ours = Counter(_norm_key(r.key()) for r in validate_files([spec["data"]], shapes, ont=[spec["model"]]))
        out["kitkb_results"] = sum(ours.values())
        out["same_results"] = ours == theirs
        out["only_kitkb"] = [repr(k) for k in (ours - theirs)][:10]
        out["only_pyshacl"] = [repr(k) for k in (theirs - ours)][:10]
    return out


def child_main(engine: str, spec_json: str) -> None:
    spec = json.loads(spec_json)
    result = child_kitkb(spec) if engine == "kitkb" else child_pyshacl(spec)
    usage = resource.getrusage(resource.RUSAGE_SELF)
    result["maxrss_mb"] = usage.ru_maxrss / 1024
    result.setdefault("cpu_s", usage.ru_utime + usage.ru_stime)
    print("RESULT " + json.dumps(result))


def run_child(engine: str, spec: dict, timeout: float | None) -> dict:
    cmd = [sys.executable, str(Path(__file__).resolve()), "--child", engine, "--spec", json.dumps(spec)]
    # through a small launcher, so the child's ru_maxrss does not start at this (big) process's
    # size: Linux keeps the peak RSS across fork and exec (see run_e2e)
    cmd = [sys.executable, "-c", "import subprocess, sys; sys.exit(subprocess.run(sys.argv[1:]).returncode)", *cmd]
    t = time.perf_counter()
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, cwd=ROOT)
    wall = time.perf_counter() - t
    for line in proc.stdout.splitlines():
        if line.startswith("RESULT "):
            out = json.loads(line[7:])
            out["process_wall_s"] = wall
            return out
    raise RuntimeError(f"{engine} run failed:\n{proc.stderr[-3000:]}")


# ---------------------------------------------------------------- machine and report


def machine() -> dict:
    import pyoxigraph
    import pyshacl
    import rdflib

    cpu = "unknown"
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
        mem = next(line for line in Path("/proc/meminfo").read_text().splitlines() if line.startswith("MemTotal"))
        mem_gb = round(int(mem.split()[1]) / 1024 / 1024, 1)
    except (OSError, StopIteration):
        mem_gb = None
    return {
        "nproc": os.cpu_count(),
        "memory_gb": mem_gb,
        "cpu": cpu,
        "python": platform.python_version(),
        "rdflib": rdflib.__version__,
        "pyshacl": pyshacl.__version__,
        "pyoxigraph": pyoxigraph.__version__,
        "load_average": os.getloadavg()[0],
    }


def _fmt(x: float | None, nd: int = 1) -> str:
    return "-" if x is None else f"{x:,.{nd}f}"


def table(store: dict, dataset: str) -> str:
    rows = [
        "| parts | triples (data+model) | kitkb parse s | kitkb validate s | kitkb total s (median) | kitkb CPU s "
        "| kitkb peak MB | pySHACL total s | pySHACL CPU s | pySHACL peak MB | speed-up wall / CPU "
        "| results kitkb / pySHACL | same results |",
        "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|",
    ]
    sizes = sorted({int(k.split(":")[1]) for k in store if k.startswith(dataset + ":")})
    for n in sizes:
        k = store.get(f"{dataset}:{n}:kitkb")
        p = store.get(f"{dataset}:{n}:pyshacl")
        speed = "-"
        if k and p:
            speed = f"{p['total_s'] / k['total_s']:,.0f}x"
            if k.get("cpu_s") and p.get("cpu_s"):
                speed += f" / {p['cpu_s'] / k['cpu_s']:,.0f}x"
        same = "-"
        if p and "same_results" in p:
            same = "yes" if p["same_results"] else "**no**"
        res = f"{k['results'] if k else '-'} / {p['results'] if p else 'not run'}"
        rows.append(
            f"| {n:,} | {(k or p)['triples']:,} | {_fmt(k and k['parse_s'])} | {_fmt(k and k['validate_s'])} "
            f"| {_fmt(k and k['total_s'])} | {_fmt(k and k.get('cpu_s'))} | {_fmt(k and k['maxrss_mb'], 0)} "
            f"| {_fmt(p and p['total_s'])} | {_fmt(p and p.get('cpu_s'))} "
            f"| {_fmt(p and p['maxrss_mb'], 0)} | {speed} | {res} | {same} |"
        )
    return "\n".join(rows)


def e2e_table(store: dict) -> str:
    rows = [
        "| parts | triples | file MB | wall s (median) | CPU s | peak MB | exit | report lines (with line no.) | runs |",
        "|---:|---:|---:|---:|---:|---:|---:|---:|---|",
    ]
    for n in sorted(int(k.split(":")[1]) for k in store if k.startswith("e2e:")):
        e = store[f"e2e:{n}:kitkb-validate"]
        rows.append(f"| {n:,} | {e['triples']:,} | {e['bytes'] / 1e6:,.0f} | {_fmt(e['wall_s'])} | {_fmt(e['cpu_s'])} "
                    f"| {_fmt(e['maxrss_mb'], 0)} | {e['exit']} | {e['diagnostics']} ({e['with_line']}) "
                    f"| {', '.join(f'{x:.1f}' for x in e['all_wall_s'])} s |")
    return "\n".join(rows)


def render(store: dict, info: dict) -> str:
    parts = [
        "## Validation",
        "",
        "SHACL validation of a generated kitting workstation with about 1% injected violations. First",
        "the end-to-end `kitkb validate` command, then the engine-only tables (kitkb's engine next to",
        "plain pySHACL): whole run in one process: parse data and model, read shapes, validate. `kitkb` is",
        "`kb.shacl` (data parsed with pyoxigraph, index in Python dictionaries, SHACL-SPARQL",
        "constraints run once over the graph in pyoxigraph); `pySHACL` is `pyshacl.validate(data,",
        "shacl_graph=shapes, ont_graph=model)` with default options on rdflib-parsed graphs. Peak",
        "memory is `ru_maxrss` of a fresh subprocess per run. kitkb times are medians of the runs",
        "listed; pySHACL ran once per size (\"-\": not run, it takes minutes to hours). CPU s is user +",
        "system time of the process (the steadier figure on a shared machine). \"same results\"",
        "compares the multiset of (focus, component, source shape, path, value) of both engines on",
        "the same files. Reproduce with `.venv/bin/python benchmarks/bench_validate.py`",
        "(`--pyshacl-big` also times pySHACL at 10k and 50k parts).",
        "",
    ]
    if any(k.startswith("e2e:") for k in store):
        parts += [
            "### End to end: `kitkb validate INIT.ttl`",
            "",
            "The whole user-facing command in a fresh process: load the file and the model it imports",
            "(rdflib terms, per-file triple views), the Python rules, the fast SHACL engine over data +",
            "model, report with file:line (lines looked up only for the nodes reported). From 100,000",
            "triples on, SHACL runs in a forked helper that shares the shapes with a child of its own",
            "while the command's process runs the Python rules (docs/architecture.md). Generated",
            "scenario with one kit (`kitkb scenario generate --parts N --kits 1 --seed 1`) plus the ~1%",
            "injected violations above, saved as N-Triples (`init.ttl`). Wall seconds of the `kitkb`",
            "process; CPU seconds (user + system) of it and its helper processes; peak memory",
            "(`ru_maxrss`: the largest of those processes); median of the runs listed.",
            "",
            e2e_table(store),
            "",
        ]
        notes = sorted({_run_note(n, v) for n, v in store.items() if n.startswith("e2e:")})
        parts += ["Runs (date, 1-minute load average when the run started, CPU):", ""]
        parts += [f"- {n}" for n in notes] + [""]
        if store.get("e2e-note"):
            parts += [store["e2e-note"], ""]
    parts += ["The tables below are engine-only: `kb.shacl` on the same kind of data (kits =",
              "parts / 10), without the loader, the Python rules or the report.", ""]
    for dataset, title in (("real", "Generated scenarios (kb.scenario) with the shipped shapes and rules"),
                           ("synthetic", "Synthetic workstation (benchmarks/synthetic_kitting.py, 10 node shapes)")):
        if any(k.startswith(dataset + ":") for k in store):
            parts += [f"### {title}", "", table(store, dataset), ""]
            notes = sorted({_run_note(n, v) for n, v in store.items() if n.startswith(dataset + ":")})
            parts += ["Runs (date, 1-minute load average when the run started, CPU):", ""]
            parts += [f"- {n}" for n in notes] + [""]
    parts += [
        f"Machines: {info['nproc']} cores, {info['memory_gb']} GB RAM (the CPU of each run is listed with it); "
        f"Python {info['python']},",
        f"rdflib {info['rdflib']}, pySHACL {info['pyshacl']}, pyoxigraph {info['pyoxigraph']}.",
        "The machine was shared with other jobs while these ran (see the load averages): wall times",
        "are pessimistic and depend on the load at the time, so compare engines by the CPU columns",
        "when their runs saw different loads. On an idle machine the kitkb wall times approach CPU s.",
        "",
    ]
    return "\n".join(parts)


def _run_note(name: str, run: dict) -> str:
    return f"{name}: {run.get('date', '?')}, load average {run.get('load_average', '?')}, {run.get('cpu', '?')}"


def write_doc(section: str) -> None:
    DOC.parent.mkdir(parents=True, exist_ok=True)
    text = DOC.read_text() if DOC.exists() else "# Benchmarks\n\nOne section per benchmark.\n"
    pattern = re.compile(r"^## Validation\n.*?(?=^## |\Z)", re.S | re.M)
    if pattern.search(text):
        text = pattern.sub(lambda _: section, text)
    else:
        text = text.rstrip("\n") + "\n\n" + section
    DOC.write_text(text.rstrip("\n") + "\n")


def save(store: dict, mine: dict) -> dict:
    """Merge this run's new entries into the results file (re-read first: runs may overlap)."""
    RESULTS.parent.mkdir(parents=True, exist_ok=True)
    current = json.loads(RESULTS.read_text()) if RESULTS.exists() else {}
    current.update(mine)
    RESULTS.write_text(json.dumps(current, indent=1, sort_keys=True))
    return current


# ---------------------------------------------------------------- against a baseline checkout

BASELINE_SECTION = "SHACL conformance and users' shapes"
#: Users' shapes for the ``--shapes`` runs: a pattern on every part's serial number, a count on
#: every parts vessel, a SPARQL rule per kit tray (what a plant's naming rules look like).
PLANT_SHAPES = """@prefix sh: <http://www.w3.org/ns/shacl#> .
@prefix ktw: <https://w3id.org/kitkb/kitting#> .
@prefix plant: <https://example.org/plant#> .
plant:SerialNumbers a sh:NodeShape ; sh:targetClass ktw:Part ;
    sh:property [ sh:path ktw:hasPart_SerialNumber ; sh:pattern "^[a-z0-9_]+$" ;
                  sh:message "serial numbers are lower-case letters, digits and _" ] .
plant:VesselSize a sh:NodeShape ; sh:targetClass ktw:PartsVessel ;
    sh:property [ sh:path ktw:hasPartsVessel_Part ; sh:maxCount 100000 ] .
plant:KitTraySku a sh:NodeShape ; sh:targetClass ktw:KitTray ;
    sh:sparql [ sh:message "a kit tray without a SKU" ;
                sh:select "SELECT $this WHERE { FILTER NOT EXISTS { $this ktw:hasSkuObject_Sku ?s } }" ] .
"""

_W3C_CHILD = """
import json, logging, sys, warnings
sys.path.insert(0, sys.argv[1])
warnings.simplefilter("ignore")
logging.disable(logging.CRITICAL)
from pathlib import Path
from collections import Counter
from rdflib import Graph, BNode, Namespace, RDF
from rdflib.collection import Collection
MF = Namespace("http://www.w3.org/2001/sw/DataAccess/tests/test-manifest#")
SHT = Namespace("http://www.w3.org/ns/shacl-test#")
SH = Namespace("http://www.w3.org/ns/shacl#")
root, engine = Path(sys.argv[2]), sys.argv[3]
def parse(p):
    return Graph().parse(p, format="turtle", publicID=p.as_uri())
def entries(m):
    g = parse(m)
    for inc in g.objects(None, MF.include):
        yield from entries(Path(str(inc)[7:]))
    for head in g.objects(None, MF.entries):
        for e in Collection(g, head):
            if (e, RDF.type, SHT.Validate) in g:
                yield g, e
def row(values):
    return tuple("_:" if isinstance(v, BNode) else v for v in values)
passed, total = Counter(), Counter()
for g, e in entries(root / "manifest.ttl"):
    section = str(e)[len(root.as_uri()) + 1:].split("/")[0]
    total[section] += 1
    act, res = g.value(e, MF.action), g.value(e, MF.result)
    data, shapes = parse(Path(str(g.value(act, SHT.dataGraph))[7:])), parse(Path(str(g.value(act, SHT.shapesGraph))[7:]))
    keys = (SH.focusNode, SH.resultPath, SH.value, SH.sourceShape, SH.sourceConstraintComponent, SH.resultSeverity)
    try:
        if engine == "pyshacl":
            import pyshacl
            from kb.shacl.fallback import results_from_report
            _, report, _ = pyshacl.validate(data, shacl_graph=shapes, inference="none", advanced=True, allow_warnings=True)
            results = results_from_report(report)
        else:
            from kb.shacl import validate_graph
            results = validate_graph(data, shapes)
        got = Counter(row((r.focus, r.path, r.value, r.source_shape, r.component, r.severity)) for r in results)
    except Exception:
        got = None
    if res == SHT.Failure:
        passed[section] += got is None
    elif got is not None:
        want = Counter(row([g.value(r, k) for k in keys]) for r in g.objects(res, SH.result))
        passed[section] += got == want and (not got) == bool(g.value(res, SH.conforms).value)
print(json.dumps({"total": dict(total), "passed": dict(passed)}))
"""


def w3c_counts(tree: Path, engine: str = "kitkb") -> dict:
    """Entries of the W3C SHACL suite passed per section by checkout ``tree``'s engine (or
    pySHACL): the same comparison as tests/test_w3c_shacl.py, on rdflib graphs."""
    suite = ROOT / "tests" / "data" / "w3c-shacl" / "tests"
    done = subprocess.run([sys.executable, "-c", _W3C_CHILD, str(tree), str(suite), engine],
                          capture_output=True, text=True, check=True, cwd=ROOT)
    return json.loads(done.stdout.strip().splitlines()[-1])


def baseline_run(baseline: Path, sizes: list[int], runs: int, workdir: Path) -> dict:
    """Both checkouts on the same files, taking turns; the W3C suite counted for both."""
    store: dict = {"baseline": str(baseline), "baseline_rev": _rev(baseline), "rev": _rev(ROOT),
                   "date": dt.datetime.now(dt.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
                   "load_average": round(os.getloadavg()[0], 1), "machine": machine(), "sizes": {}}
    shapes = workdir / "plant-shapes.ttl"
    workdir.mkdir(parents=True, exist_ok=True)
    shapes.write_text(PLANT_SHAPES)
    sides = {"before": (tree_command(baseline), []), "after": (tree_command(ROOT), []),
             "after, --shapes": (tree_command(ROOT), ["--shapes", str(shapes)])}
    for n in sizes:
        out = workdir / f"e2e-{n}"
        out.mkdir(parents=True, exist_ok=True)
        spec = make_e2e(n, out)
        print(f"\n{n} parts: {spec['data']}")
        for command, extra in sides.values():  # warm-up: byte-compiled modules, file cache
            run_e2e(spec["data"], command, extra)
        got: dict[str, list[dict]] = {side: [] for side in sides}
        for i in range(runs):
            order = list(sides) if i % 2 == 0 else list(reversed(sides))
            for side in order:
                r = run_e2e(spec["data"], *sides[side])
                got[side].append(r)
                print(f"  {side}: wall {r['wall_s']:.2f} s, CPU {r['cpu_s']:.2f} s, {r['summary']}")
        row = {"triples": spec["triples"], "bytes": spec["bytes"]}
        for side, rs in got.items():
            row[side] = {k: statistics.median(r[k] for r in rs) for k in ("wall_s", "cpu_s", "maxrss_mb")}
            row[side]["all_wall_s"] = [round(r["wall_s"], 2) for r in rs]
            row[side]["summary"] = rs[0]["summary"]
        row["same_report"] = all(r["report"] == got["before"][0]["report"] for side in ("before", "after")
                                 for r in got[side])
        store["sizes"][str(n)] = row
    print("\nW3C SHACL suite ...")
    store["w3c"] = {"before": w3c_counts(baseline), "after": w3c_counts(ROOT), "pyshacl": w3c_counts(ROOT, "pyshacl")}
    return store


def _rev(tree: Path) -> str:
    try:
        return subprocess.run(["git", "-C", str(tree), "rev-parse", "--short", "HEAD"], capture_output=True,
                              text=True, check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "?"


def render_baseline(store: dict) -> str:
    m = store["machine"]
    w = store["w3c"]
    lines = [
        f"## {BASELINE_SECTION}",
        "",
        "Issue 20: kitkb's SHACL engine on the W3C SHACL test suite, and users' shapes files",
        "(`kitkb validate --shapes`, `kitkb shacl`), without making `kitkb validate` slower. Command:",
        f"`.venv/bin/python benchmarks/bench_validate.py --baseline DIR --baseline-sizes ...` with DIR a",
        f"worktree of the commit the work started from (`{store['baseline_rev']}`; after: `{store['rev']}` plus",
        "the files of the run). Run " + f"{store['date']}, load average {store['load_average']} at the start;",
        f"{m['nproc']} cores, {m['memory_gb']} GB, {m['cpu']}; Python {m['python']}, rdflib {m['rdflib']}, "
        f"pySHACL {m['pyshacl']}, pyoxigraph {m['pyoxigraph']}.",
        "",
        "W3C SHACL test suite (`tests/data/w3c-shacl`, every `sht:Validate` entry; the comparison of",
        "tests/test_w3c_shacl.py on rdflib graphs: `sh:conforms` and the results' focus, path, value,",
        "source shape, component and severity, blank nodes loosely; a `sht:Failure` entry passes when",
        "the shapes are refused):",
        "",
        "| section | entries | pySHACL | kitkb before | kitkb after |",
        "|---|---:|---:|---:|---:|",
    ]
    for section, total in w["after"]["total"].items():
        lines.append(f"| {section} | {total} | {w['pyshacl']['passed'].get(section, 0)} "
                     f"| {w['before']['passed'].get(section, 0)} | {w['after']['passed'].get(section, 0)} |")
    lines += [
        "",
        "`kitkb validate INIT.ttl` end to end (the files of the Validation section: one kit, ~1%",
        "injected violations, N-Triples), whole process as the console script starts it, the two",
        "checkouts taking turns after one warm-up each; \"after, --shapes\" adds a users' shapes file",
        "(a pattern on every part, a count on every parts vessel, a SPARQL rule per kit tray). Median",
        "wall and CPU seconds (CPU of the process and its helpers: the steadier figure on a shared",
        "machine); \"same report\": before and after print the same report, byte for byte.",
        "",
        "| parts | triples | before: wall s (CPU s) | after: wall s (CPU s) | after / before, wall (CPU) "
        "| after, --shapes: wall s (CPU s) | same report | runs (wall s: before; after) |",
        "|---:|---:|---:|---:|---:|---:|---|---|",
    ]
    for n, row in sorted(store["sizes"].items(), key=lambda kv: int(kv[0])):
        b, a, u = row["before"], row["after"], row["after, --shapes"]
        lines.append(
            f"| {int(n):,} | {row['triples']:,} | {b['wall_s']:.2f} ({b['cpu_s']:.2f}) | {a['wall_s']:.2f} "
            f"({a['cpu_s']:.2f}) | {a['wall_s'] / b['wall_s']:.2f} ({a['cpu_s'] / b['cpu_s']:.2f}) "
            f"| {u['wall_s']:.2f} ({u['cpu_s']:.2f}) | {'yes' if row['same_report'] else '**no**'} "
            f"| {', '.join(f'{x:.1f}' for x in b['all_wall_s'])}; {', '.join(f'{x:.1f}' for x in a['all_wall_s'])} |")
    notes = store.get("note")
    if notes:
        lines += ["", notes]
    return "\n".join(lines) + "\n"


def write_section(title: str, section: str) -> None:
    """Replace (or append) the section ``## title`` of docs/benchmarks.md."""
    text = DOC.read_text() if DOC.exists() else "# Benchmarks\n"
    pattern = re.compile(rf"^## {re.escape(title)}\n.*?(?=^## |\Z)", re.S | re.M)
    if pattern.search(text):
        text = pattern.sub(lambda _: section + "\n", text)
    else:
        text = text.rstrip("\n") + "\n\n" + section
    DOC.write_text(text.rstrip("\n") + "\n")


# ---------------------------------------------------------------- main


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[1000, 10000, 50000])
    ap.add_argument("--repeat", type=int, default=3, help="kitkb runs per size (median reported)")
    ap.add_argument("--pyshacl-sizes", type=int, nargs="*", default=[1000])
    ap.add_argument("--pyshacl-big", action="store_true", help="also time pySHACL at 10k and 50k parts")
    ap.add_argument("--engines", nargs="+", default=["kitkb", "pyshacl"], choices=["kitkb", "pyshacl"])
    ap.add_argument("--synthetic", action="store_true", help="use the synthetic data and shapes")
    ap.add_argument("--workdir", type=Path, default=Path("/tmp/kitkb-bench-validate"))
    ap.add_argument("--no-doc", action="store_true", help="do not rewrite docs/benchmarks.md")
    ap.add_argument("--render-only", action="store_true", help="only rewrite the doc section from the results file")
    ap.add_argument("--e2e-sizes", type=int, nargs="*", default=[1000, 10000, 50000],
                    help="sizes for the end-to-end `kitkb validate` runs (none: skip them)")
    ap.add_argument("--only-e2e", action="store_true", help="only the end-to-end runs")
    ap.add_argument("--baseline", type=Path, metavar="DIR",
                    help="compare with this checkout (a git worktree of an earlier commit) and count the W3C "
                         "SHACL suite; only the section \"SHACL conformance and users' shapes\" is rewritten")
    ap.add_argument("--baseline-sizes", type=int, nargs="+", default=[10000], help="parts (default 10000)")
    ap.add_argument("--baseline-runs", type=int, default=5, help="runs per checkout and size (default 5)")
    ap.add_argument("--baseline-note", metavar="TEXT",
                    help="with --render-only: a paragraph under the baseline section's tables (kept in the results)")
    ap.add_argument("--child", choices=["kitkb", "pyshacl"], help=argparse.SUPPRESS)
    ap.add_argument("--spec", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.child:
        child_main(args.child, args.spec)
        return
    if args.render_only:
        store = json.loads(RESULTS.read_text())
        if "baseline-comparison" in store:
            if args.baseline_note:
                store["baseline-comparison"]["note"] = args.baseline_note
                save({}, {"baseline-comparison": store["baseline-comparison"]})
            write_section(BASELINE_SECTION, render_baseline(store["baseline-comparison"]))
            store = {k: v for k, v in store.items() if k != "baseline-comparison"}
        write_doc(render(store, machine()))
        return
    if args.baseline is not None:
        found = baseline_run(args.baseline.resolve(), args.baseline_sizes, args.baseline_runs, args.workdir)
        saved = save({}, {"baseline-comparison": found})["baseline-comparison"]
        section = render_baseline(saved)
        print("\n" + section)
        if not args.no_doc:
            write_section(BASELINE_SECTION, section)
            print(f"wrote {DOC}")
        return
    real = not args.synthetic and (ROOT / "kb" / "scenario.py").exists() and (ROOT / "shapes" / "kitting-shapes.ttl").exists()
    dataset = "real" if real else "synthetic"
    pysizes = set(args.pyshacl_sizes) | ({10000, 50000} if args.pyshacl_big else set())
    store = json.loads(RESULTS.read_text()) if RESULTS.exists() else {}
    info = machine()
    print(f"data set: {dataset}; machine: {info}")
    produced: set[str] = set()  # keys measured by this run: the only ones it writes back
    for n in args.e2e_sizes:
        out = args.workdir / f"e2e-{n}"
        out.mkdir(parents=True, exist_ok=True)
        spec = make_e2e(n, out)
        print(f"\n{n} parts end to end: {spec['data']} (injected {spec['injected']})")
        stamp = {"cpu": info["cpu"], "date": dt.datetime.now(dt.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
                 "load_average": round(os.getloadavg()[0], 1)}
        runs = [run_e2e(spec["data"]) for _ in range(3 if n <= 10000 else 1)]
        for r in runs:
            print(f"  kitkb validate: {json.dumps({k: (round(v, 2) if isinstance(v, float) else v) for k, v in r.items()})}")
        med = {k: statistics.median(r[k] for r in runs) for k in ("wall_s", "cpu_s", "maxrss_mb")}
        key = f"e2e:{n}:kitkb-validate"
        produced.add(key)
        store[key] = {**runs[0], **med, **spec, "all_wall_s": [round(r["wall_s"], 2) for r in runs], **stamp}
        store = save(store, {k: store[k] for k in produced})
    for n in ([] if args.only_e2e else args.sizes):
        out = args.workdir / f"{dataset}-{n}"
        out.mkdir(parents=True, exist_ok=True)
        spec = make_real(n, out) if real else make_synthetic(n, out)
        print(f"\n{n} parts: {spec['data']} (injected {spec['injected']})")
        stamp = {"cpu": info["cpu"], "date": dt.datetime.now(dt.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
                 "load_average": round(os.getloadavg()[0], 1)}
        if "kitkb" in args.engines:
            runs = [run_child("kitkb", spec, None) for _ in range(args.repeat)]
            for r in runs:
                print(f"  kitkb: {json.dumps({k: (round(v, 2) if isinstance(v, float) else v) for k, v in r.items()})}")
            med = {k: statistics.median(r[k] for r in runs)
                   for k in ("parse_s", "shapes_s", "validate_s", "total_s", "maxrss_mb", "cpu_s")}
            produced.add(f"{dataset}:{n}:kitkb")
            store[f"{dataset}:{n}:kitkb"] = {**runs[0], **med, "runs": len(runs),
                                             "all_total_s": [round(r["total_s"], 2) for r in runs], **stamp}
        if "pyshacl" in args.engines and n in pysizes:
            spec_cmp = {**spec, "compare": True}
            p = run_child("pyshacl", spec_cmp, None)
            print(f"  pyshacl: {json.dumps({k: (round(v, 2) if isinstance(v, float) else v) for k, v in p.items()})}")
            print(f"  kitkb results equal pySHACL's: {p['same_results']} ({p['kitkb_results']} vs {p['results']})")
            produced.add(f"{dataset}:{n}:pyshacl")
            store[f"{dataset}:{n}:pyshacl"] = {**p, **stamp}
        store = save(store, {k: store[k] for k in produced})
    store = json.loads(RESULTS.read_text()) if RESULTS.exists() else store
    print()
    print(table(store, dataset))
    if not args.no_doc:
        write_doc(render(store, info))
        print(f"\nwrote {DOC}")


if __name__ == "__main__":
    main()
