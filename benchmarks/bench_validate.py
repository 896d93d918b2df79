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


def run_e2e(data: str) -> dict:
    """Run ``kitkb validate DATA`` once: wall and CPU seconds, peak MB, exit code, report lines.

    The command is started by a small launcher process: a process forked from this one (big
    after generating the data) would inherit its peak RSS (Linux keeps ``ru_maxrss`` across
    fork and exec), and the peak memory would be this benchmark's, not kitkb's.
    """
    done = subprocess.run([sys.executable, "-c", _LAUNCHER, json.dumps([*kitkb_command(), "validate", data]),
                           str(ROOT)], capture_output=True, text=True, check=True)
    got = json.loads(done.stdout)
    if got["code"] not in (0, 1):
        raise RuntimeError(f"kitkb validate failed ({got['code']}):\n{got['stderr']}")
    lines = got["stdout"].splitlines()
    return {"wall_s": got["wall_s"], "cpu_s": got["cpu_s"], "maxrss_mb": got["maxrss_kb"] / 1024,
            "exit": got["code"], "diagnostics": max(0, len(lines) - 1),
            "with_line": sum(1 for line in lines[:-1] if re.match(r"^[^:]+:\d+: ", line)),
            "summary": lines[-1] if lines else ""}


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
    ap.add_argument("--child", choices=["kitkb", "pyshacl"], help=argparse.SUPPRESS)
    ap.add_argument("--spec", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.child:
        child_main(args.child, args.spec)
        return
    if args.render_only:
        write_doc(render(json.loads(RESULTS.read_text()), machine()))
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
