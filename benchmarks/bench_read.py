"""Reading files (``kb.io.load_file``): this checkout against a baseline checkout, taking turns.

What issue 26's points 4 and 6 added to every read (the declared encoding looked up, internal
DTD entities expanded by kitkb, ``file:`` paths checked, NIST's 2012 namespace looked for)
must not make the common files slower. Each side is a fresh process with its tree first on
``PYTHONPATH`` that loads each file once (warm-up) then ``--repeat`` times, reporting the
median; the sides take turns ``--rounds`` times and the medians of those are compared.
Files: a generated workstation (``kitkb scenario generate --parts N``) as Turtle, the same as
RDF/XML, the same as Protégé writes RDF/XML (a DOCTYPE of entities, ``&ktw;`` in every
``rdf:resource``/``rdf:about``), and NIST's ``kittingInstancesInit1.owl`` (functional syntax)::

    git archive dbb7333 | tar -x -C /tmp/kitkb-before     # or git worktree add
    .venv/bin/python benchmarks/bench_read.py --baseline /tmp/kitkb-before --parts 10000

Rewrites the section ``## Reading files (kb.io)`` of docs/benchmarks.md.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import re
import statistics
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SECTION = "Reading files (kb.io)"
_PROBE = """
import json, sys, time
from kb.io import load_file
out = {}
for path in json.loads(sys.argv[1]):
    load_file(path)
    times = []
    for _ in range(int(sys.argv[2])):
        t = time.perf_counter(); load_file(path); times.append(time.perf_counter() - t)
    times.sort()
    out[path] = times[len(times) // 2]
print(json.dumps(out))
"""


def make_files(work: Path, parts: int) -> dict[str, Path]:
    """The files read: name -> path (made once)."""
    work.mkdir(parents=True, exist_ok=True)
    ttl = work / f"s{parts}" / "init.ttl"
    kitkb = [sys.executable, "-m", "kb.cli", "-q"]
    if not ttl.exists():
        subprocess.run(kitkb + ["scenario", "generate", "--parts", str(parts), "--kits", "1", "-o",
                                str(ttl.parent)], check=True, cwd=ROOT)
    rdf = work / f"s{parts}.owl"
    if not rdf.exists():
        subprocess.run(kitkb + ["convert", str(ttl), "-o", str(rdf)], check=True, cwd=ROOT)
    protege = work / f"s{parts}-protege.owl"
    if not protege.exists():
        text = rdf.read_text("utf-8")
        head, _, body = text.partition("<rdf:RDF")
        dtd = ('<!DOCTYPE rdf:RDF [\n    <!ENTITY ktw "https://w3id.org/kitkb/kitting#" >\n'
               '    <!ENTITY xsd "http://www.w3.org/2001/XMLSchema#" >\n]>\n')
        body = re.sub(r'(rdf:(?:resource|about|datatype)=")https://w3id\.org/kitkb/kitting#', r"\1&ktw;", body)
        body = body.replace('"http://www.w3.org/2001/XMLSchema#', '"&xsd;')
        protege.write_text(head + dtd + "<rdf:RDF" + body, "utf-8")
    files = {f"Turtle, {parts:,} parts": ttl, f"RDF/XML, {parts:,} parts": rdf,
             f"Protégé RDF/XML (DTD entities), {parts:,} parts": protege}
    nist = ROOT.parent / "shared" / "nist" / "kittingInstancesInit1.owl"
    if nist.is_file():
        files["NIST kittingInstancesInit1.owl (functional syntax)"] = nist
    return files


def probe(tree: Path, files: dict[str, Path], repeat: int) -> dict[str, float]:
    env = {**os.environ, "PYTHONPATH": str(tree)}
    done = subprocess.run([sys.executable, "-c", _PROBE, json.dumps([str(p) for p in files.values()]), str(repeat)],
                          env=env, capture_output=True, text=True, check=True, cwd=tree)
    seconds = json.loads(done.stdout)
    return {name: seconds[str(path)] for name, path in files.items()}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--baseline", type=Path, required=True, help="a checkout of the baseline revision")
    ap.add_argument("--parts", type=int, default=10000)
    ap.add_argument("--repeat", type=int, default=5, help="loads of each file per process (median)")
    ap.add_argument("--rounds", type=int, default=3, help="turns each side takes")
    ap.add_argument("--work", type=Path, default=Path("/tmp/kitkb-bench-read"))
    args = ap.parse_args()
    files = make_files(args.work, args.parts)
    runs: dict[str, list[dict[str, float]]] = {"before": [], "after": []}
    load = []
    for _ in range(args.rounds):
        for side, tree in (("before", args.baseline), ("after", ROOT)):
            load.append(os.getloadavg()[0])
            runs[side].append(probe(tree, files, args.repeat))
    result = {name: {side: statistics.median(r[name] for r in runs[side]) for side in runs} for name in files}
    store = {"baseline": str(args.baseline), "parts": args.parts, "repeat": args.repeat, "rounds": args.rounds,
             "machine": f"{platform.processor() or platform.machine()}, {os.cpu_count()} cores",
             "load": [round(x, 2) for x in load], "seconds": result}
    out = ROOT / "benchmarks" / "results" / "read.json"
    out.write_text(json.dumps(store, indent=1) + "\n")
    print(render(store))


def render(store: dict) -> str:
    rows = ["| file | baseline (s) | this checkout (s) | ratio |", "|---|---|---|---|"]
    for name, s in store["seconds"].items():
        rows.append(f"| {name} | {s['before']:.3f} | {s['after']:.3f} | {s['after'] / s['before']:.2f} |")
    return "\n".join(rows)


if __name__ == "__main__":
    main()
