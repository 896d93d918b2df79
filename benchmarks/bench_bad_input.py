"""Bad-input campaign: broken files fed to every kitkb command that reads files.

Seeds (a generated 3-part scenario in Turtle and RDF/XML, NIST's OWL functional syntax states,
CRCL text and XML, generated and NIST PDDL, a world-model database) are mutated — truncated,
garbled, shuffled, numbers made NaN / infinite / huge, huge literals, wrong encodings, empty,
random binary, cycles in the transformation tree, deep nesting — and each mutant is given to
the command that reads it. Every outcome must be exit 0, 1 or 2 with one error line (never a
traceback nor exit 3), every input file and database byte-identical afterwards, and no
temporary file left beside an output.

The same engine drives ``tests/test_bad_input.py`` (hypothesis draws the mutations there; here a
seeded ``random.Random`` does), so a mutation's parameters come from one ``pick(n)`` function.

    .venv/bin/python benchmarks/bench_bad_input.py                  # 3,000 inputs, writes docs/benchmarks.md
    .venv/bin/python benchmarks/bench_bad_input.py --inputs 200 --no-doc --subprocess 20
    .venv/bin/python benchmarks/bench_bad_input.py --render     # the section again, from results/bad_input.json
"""

from __future__ import annotations

import argparse
import contextlib
import hashlib
import io
import json
import os
import random
import re
import shutil
import signal
import sqlite3
import subprocess
import sys
import tempfile
import time
from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "benchmarks"))
sys.path.insert(0, str(ROOT / "tests"))

Pick = Callable[[int], int]  # a number in range(n)

# --- seeds ---------------------------------------------------------------------------------

#: role -> file name in the seed folder; the suffix is kept by every mutant.
SEED_FILES = {
    "ttl_init": "s3/init.ttl", "ttl_goal": "s3/goal.ttl", "rdf_init": "init.rdf",
    "ofn_init": "kittingInstancesInit1.owl", "ofn_goal": "kittingInstancesGoal1.owl",
    "crcl_text": "commands.crcl", "crcl_xml": "commands1.xml",
    "pddl_domain": "pddl/domain.pddl", "pddl_problem": "pddl/problem.pddl",
    "nist_domain": "domain-fluents.pddl", "nist_problem": "problem-fluents-a2b1c1.pddl",
    "db": "world.sqlite",
}


def family(role: str) -> str:
    """The syntax family of a seed role: what mutations that know a syntax write."""
    return {"nist_domain": "pddl", "nist_problem": "pddl", "crcl_xml": "crcl_xml"}.get(role, role.split("_")[0])


def make_seeds(folder: Path) -> dict[str, Path]:
    """Write the seed files into ``folder``; role -> path."""
    from kb.cli import main
    from shared_data import NIST_DIR

    folder.mkdir(parents=True, exist_ok=True)
    s3 = folder / "s3"
    steps = [["scenario", "generate", "--parts", "3", "-o", str(s3)],
             ["convert", str(s3 / "init.ttl"), "-o", str(folder / "init.rdf")],
             ["crcl", "convert", str(NIST_DIR / "commands1.xml"), "-o", str(folder / "commands.crcl")],
             ["generate", "pddl", str(s3 / "init.ttl"), str(s3 / "goal.ttl"), "-o", str(folder / "pddl")],
             ["db", "load", str(s3 / "init.ttl"), "--db", str(folder / "world.sqlite")]]
    for name in ("kittingInstancesInit1.owl", "kittingInstancesGoal1.owl", "commands1.xml", "domain-fluents.pddl",
                 "problem-fluents-a2b1c1.pddl"):
        shutil.copyfile(NIST_DIR / name, folder / name)
    with contextlib.redirect_stderr(io.StringIO()):
        for argv in steps:
            assert main(["-q", *argv]) == 0, argv
    return {role: folder / name for role, name in SEED_FILES.items()}


# --- mutations -----------------------------------------------------------------------------

SPECIAL_NUMBERS = ["NaN", "nan", "INF", "-INF", "inf", "-inf", "1e308", "-1e308", "1e309", "1e-320", "9" * 400,
                   "-0", "0x10", "1_000", '"NaN"^^xsd:double', '"INF"^^xsd:double', '"-INF"^^xsd:double',
                   '"1e999"^^xsd:double', '"abc"^^xsd:double', '"NaN"^^xsd:decimal']
NUMBER = re.compile(rb"(?<![\w.#:/\-])-?\d+(?:\.\d+)?(?:[eE][+-]?\d+)?(?![\w.])")
SIZES = [1_000, 100_000, 1_000_000]
DEPTHS = [50, 1_000, 20_000, 200_000]
NESTING = {  # family -> (opening, closing) of one level
    "ttl": (b"[ <https://w3id.org/kitkb/kitting#p> ", b" ]"), "rdf": (b"<rdf:Description><a:b>", b"</a:b></rdf:Description>"),
    "ofn": (b"ObjectIntersectionOf(", b")"), "crcl": (b"{", b"}"), "pddl": (b"(and ", b")"), "db": (b"(", b")"),
}
NESTING["crcl_xml"] = (b"<Waypoint>", b"</Waypoint>")
NAME = re.compile(rb"(?:^|[\s(])(:[A-Za-z_][\w-]*)")


def _lines(data: bytes) -> list[bytes]:
    return data.split(b"\n")


def _truncate(data: bytes, pick: Pick, fam: str) -> bytes:
    return data[:pick(len(data) + 1)]


def _flip(data: bytes, pick: Pick, fam: str) -> bytes:
    out = bytearray(data or b"\0")
    for _ in range(1 + pick(8)):
        i = pick(len(out))
        out[i] ^= 1 + pick(255)
    return bytes(out)


def _insert(data: bytes, pick: Pick, fam: str) -> bytes:
    i = pick(len(data) + 1)
    junk = bytes(pick(256) for _ in range(1 + pick(16)))
    return data[:i] + junk + data[i:]


def _delete(data: bytes, pick: Pick, fam: str) -> bytes:
    i = pick(len(data) + 1)
    return data[:i] + data[i + 1 + pick(200):]


def _shuffle_lines(data: bytes, pick: Pick, fam: str) -> bytes:
    lines = _lines(data)
    for _ in range(1 + pick(6)):
        i, j = pick(len(lines)), pick(len(lines))
        lines[i], lines[j] = lines[j], lines[i]
    return b"\n".join(lines)


def _duplicate_lines(data: bytes, pick: Pick, fam: str) -> bytes:
    lines = _lines(data)
    i = pick(len(lines))
    return b"\n".join(lines[:i + 1] + lines[i:i + 1 + pick(30)] + lines[i + 1:])


def _numbers(data: bytes, pick: Pick, fam: str) -> bytes:
    spans = [m.span() for m in NUMBER.finditer(data)]
    if not spans:
        return data + SPECIAL_NUMBERS[pick(len(SPECIAL_NUMBERS))].encode()
    chosen = sorted({spans[pick(len(spans))] for _ in range(1 + pick(5))}, reverse=True)
    for start, end in chosen:
        data = data[:start] + SPECIAL_NUMBERS[pick(len(SPECIAL_NUMBERS))].encode() + data[end:]
    return data


def _huge_literal(data: bytes, pick: Pick, fam: str) -> bytes:
    size = SIZES[pick(len(SIZES))]
    how = pick(3)
    if how == 0:  # a string literal (or an XML text) made huge
        m = re.search(rb'"[^"\n]*"', data) if fam != "crcl_xml" else re.search(rb">[^<\n]+<", data)
        if m:
            inner = b"\xc3\xa9A" * (size // 2)
            return data[:m.start() + 1] + inner + data[m.end() - 1:]
    spans = [m.span() for m in NUMBER.finditer(data)]
    if how == 1 and spans:  # a number with ``size`` digits
        start, end = spans[pick(len(spans))]
        return data[:start] + b"7" * size + data[end:]
    i = pick(len(data) + 1)  # a huge token anywhere
    return data[:i] + b"x" * size + data[i:]


def _utf16(data: bytes, pick: Pick, fam: str) -> bytes:
    return data.decode("utf-8", "replace").encode(["utf-16", "utf-16-le", "utf-32"][pick(3)])


def _latin1(data: bytes, pick: Pick, fam: str) -> bytes:
    i = pick(len(data) + 1)
    return data[:i] + "café_ÿ".encode("latin-1") + data[i:]


def _invalid_utf8(data: bytes, pick: Pick, fam: str) -> bytes:
    i = pick(len(data) + 1)
    return data[:i] + [b"\xff\xfe", b"\xc3", b"\xed\xa0\x80", b"\x00", b"\xef\xbb\xbf"][pick(5)] + data[i:]


def _empty(data: bytes, pick: Pick, fam: str) -> bytes:
    return [b"", b"\n", b" \t\r\n", b"\xef\xbb\xbf"][pick(4)]


def _binary(data: bytes, pick: Pick, fam: str) -> bytes:
    rng = random.Random(pick(1 << 30))
    return rng.randbytes(1 + pick(50_000))


def _cycle(data: bytes, pick: Pick, fam: str) -> bytes:
    """A pose relative to its own object or to one of its descendants, or any object property
    pointed at another individual: cycles in the transformation tree and in hasX relations."""
    if fam == "ofn":
        pairs = list(re.finditer(rb"(hasPhysicalLocation_RefObject\s+)(:\w+)(\s+)(:\w+)\)", data))
        owners = dict((m.group(2), m.group(1)) for m in
                      re.finditer(rb"hasSolidObject_PrimaryLocation\s+(:\w+)\s+(:\w+)\)", data))
    else:
        pairs = list(re.finditer(rb"\n(:\w+)( a [^.]*?hasPhysicalLocation_RefObject )(:\w+)( ;| \.)", data, re.S))
        owners = {}
    names = sorted({m.group(1) for m in NAME.finditer(data)} | set(owners.values()))
    if pick(2) == 0 and pairs:  # the transformation tree: a pose refers to its own object, or below it
        m = pairs[pick(len(pairs))]
        pose = m.group(2) if fam == "ofn" else m.group(1)
        owner = owners.get(pose, pose[:-5] if pose.endswith(b"_pose") else pose)
        below = [owner] + [n for n in names if n.startswith(owner)]
        target = below[pick(len(below))]
        group = 4 if fam == "ofn" else 3
        return data[:m.start(group)] + target + data[m.end(group):]
    props = list(re.finditer(rb"(ktw:has\w+[\s]+)(:\w+)", data))
    if not props or not names:
        return data
    m = props[pick(len(props))]
    return data[:m.start(2)] + names[pick(len(names))] + data[m.end(2):]


def _deep_nesting(data: bytes, pick: Pick, fam: str) -> bytes:
    opening, closing = NESTING.get(fam, (b"(", b")"))
    depth = DEPTHS[pick(len(DEPTHS))]
    core = opening * depth + b"1" + closing * depth
    if fam == "ttl":
        core = b"\n:deep <https://w3id.org/kitkb/kitting#p> " + core + b" .\n"
    lines = _lines(data)
    i = pick(len(lines) + 1)
    balanced = pick(3) != 0
    return b"\n".join(lines[:i] + [core if balanced else opening * depth] + lines[i:])


MUTATIONS: dict[str, Callable[[bytes, Pick, str], bytes]] = {
    "truncate": _truncate, "flip": _flip, "insert": _insert, "delete": _delete, "shuffle-lines": _shuffle_lines,
    "duplicate-lines": _duplicate_lines, "numbers": _numbers, "huge-literal": _huge_literal, "utf16": _utf16,
    "latin1": _latin1, "invalid-utf8": _invalid_utf8, "empty": _empty, "binary": _binary, "cycle": _cycle,
    "deep-nesting": _deep_nesting,
}
#: mutations that make no sense for a binary SQLite database
DB_MUTATIONS = ["truncate", "flip", "insert", "delete", "empty", "binary", "sqlite-page"]


def _sqlite_page(data: bytes, pick: Pick, fam: str) -> bytes:
    """Garble a whole page of the database (a b-tree page, the schema, the header)."""
    page = int.from_bytes(data[16:18], "big") or 4096 if len(data) >= 100 else 4096
    pages = max(1, len(data) // page)
    p = pick(pages)
    rng = random.Random(pick(1 << 30))
    junk = rng.randbytes(page) if pick(2) else bytes(page)
    return data[:p * page] + junk + data[(p + 1) * page:]


MUTATIONS["sqlite-page"] = _sqlite_page


def mutate(data: bytes, kind: str, pick: Pick, fam: str) -> bytes:
    """``data`` broken by the mutation ``kind``, its parameters from ``pick``."""
    return MUTATIONS[kind](data, pick, fam)


def kinds_for(role: str) -> list[str]:
    """The mutations that apply to a seed role."""
    if role == "db":
        return DB_MUTATIONS
    return [k for k in MUTATIONS if k != "sqlite-page"]


# --- commands ------------------------------------------------------------------------------

@dataclass(frozen=True)
class Case:
    """A command reading the mutated seed ``role``: ``argv(mutant, seeds, out)``."""

    name: str
    role: str
    argv: Callable[[Path, dict[str, Path], Path], list[str]]
    weight: int = 4  # relative share of a campaign
    replaces_db: bool = False  # exit 0 may change the database after --db (db load --replace)


def _other(role: str) -> Callable[[dict[str, Path]], str]:
    return lambda seeds: str(seeds[role])


CASES = [
    Case("validate ttl", "ttl_init", lambda m, s, o: ["validate", str(m)]),
    Case("validate rdfxml", "rdf_init", lambda m, s, o: ["validate", str(m)]),
    Case("validate ofn", "ofn_init", lambda m, s, o: ["validate", str(m)]),
    Case("convert ttl", "ttl_init", lambda m, s, o: ["convert", str(m), "-o", str(o / "c.nt")]),
    Case("convert rdfxml", "rdf_init", lambda m, s, o: ["convert", str(m), "-o", str(o / "c.ttl")]),
    Case("convert ofn", "ofn_init", lambda m, s, o: ["convert", str(m), "-o", str(o / "c.owl")]),
    Case("scenario transform ttl", "ttl_init",
         lambda m, s, o: ["scenario", "transform", str(m), "-o", str(o / "t.ttl"), "--unit", "millimeter"]),
    Case("scenario transform ofn", "ofn_init",
         lambda m, s, o: ["scenario", "transform", str(m), "-o", str(o / "t.ttl"), "--yaw", "30"]),
    Case("generate pddl init", "ttl_init",
         lambda m, s, o: ["generate", "pddl", str(m), str(s["ttl_goal"]), "-o", str(o / "pddl")]),
    Case("generate pddl goal", "ttl_goal",
         lambda m, s, o: ["generate", "pddl", str(s["ttl_init"]), str(m), "-o", str(o / "pddl")]),
    Case("generate pddl ofn", "ofn_init",
         lambda m, s, o: ["generate", "pddl", str(m), str(s["ofn_goal"]), "--match-names", "-o", str(o / "pddl")]),
    Case("plan init", "ttl_init",
         lambda m, s, o: ["plan", str(m), str(s["ttl_goal"]), "-o", str(o / "plan.txt")], weight=2),
    Case("plan goal", "ttl_goal",
         lambda m, s, o: ["plan", str(s["ttl_init"]), str(m), "-o", str(o / "plan.txt")], weight=2),
    Case("plan domain.pddl", "pddl_domain",
         lambda m, s, o: ["plan", str(m), str(s["pddl_problem"]), "-o", str(o / "plan.txt")], weight=2),
    Case("plan problem.pddl", "pddl_problem",
         lambda m, s, o: ["plan", str(s["pddl_domain"]), str(m), "-o", str(o / "plan.txt")], weight=2),
    Case("plan nist problem", "nist_problem",
         lambda m, s, o: ["plan", str(s["nist_domain"]), str(m), "-o", str(o / "plan.txt"), "--timeout", "20"],
         weight=1),
    Case("db load new", "ttl_init", lambda m, s, o: ["db", "load", str(m), "--db", str(o / "new.sqlite")]),
    Case("db load --replace", "ttl_init",
         lambda m, s, o: ["db", "load", str(m), "--db", str(o / "world.sqlite"), "--replace"], replaces_db=True),
    Case("db load ofn", "ofn_init", lambda m, s, o: ["db", "load", str(m), "--db", str(o / "new.sqlite")]),
    Case("db load into db", "db", lambda m, s, o: ["db", "load", str(s["ttl_init"]), "--db", str(m)], weight=2,
         replaces_db=True),  # an empty file is a new database
    Case("db dump", "db", lambda m, s, o: ["db", "dump", "--db", str(m), "-o", str(o / "dump.ttl")]),
    Case("run init", "ttl_init",
         lambda m, s, o: ["run", str(m), str(s["ttl_goal"]), "-o", str(o / "run")], weight=1),
    Case("crcl convert text", "crcl_text", lambda m, s, o: ["crcl", "convert", str(m), "-o", str(o / "c.xml")]),
    Case("crcl convert xml", "crcl_xml", lambda m, s, o: ["crcl", "convert", str(m), "-o", str(o / "c.crcl")]),
    Case("predicates ttl", "ttl_init", lambda m, s, o: ["predicates", str(m)]),
    Case("predicates ofn", "ofn_init", lambda m, s, o: ["predicates", str(m)], weight=2),
]
CASE_BY_NAME = {c.name: c for c in CASES}


# --- one outcome ---------------------------------------------------------------------------

@dataclass
class Outcome:
    """What one command did with one mutant, and what was wrong with it (``problems``)."""

    case: str
    mutation: str
    code: int
    stderr: str
    seconds: float
    problems: list[str] = field(default_factory=list)
    real: bool = False  # run in a ``kitkb`` subprocess


def _digest(path: Path) -> str | None:
    try:
        return hashlib.sha256(path.read_bytes()).hexdigest()
    except OSError:
        return None


def _temps(folder: Path) -> list[str]:
    return sorted(str(p.relative_to(folder)) for p in folder.rglob(".*.tmp"))


#: Seconds a command may take on one mutant before it counts as a hang (exit code HANG).
TIMEOUT = 180
HANG = -1


class _Hang(BaseException):
    """Raised by the alarm in a command that ran past :data:`TIMEOUT` (a BaseException, so
    the command's own error handling does not turn it into an exit code)."""


def _alarm(signum: int, frame: object) -> None:
    raise _Hang()


def _in_process(argv: list[str]) -> tuple[int, str, str]:
    from kb.cli import main

    out, err = io.StringIO(), io.StringIO()
    previous = signal.signal(signal.SIGALRM, _alarm)
    signal.alarm(TIMEOUT)
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            code = main(argv)
        except SystemExit as exc:  # argparse (not expected: every argv here is well-formed)
            code = exc.code if isinstance(exc.code, int) else 2
        except _Hang:
            code = HANG
        finally:
            signal.alarm(0)
            signal.signal(signal.SIGALRM, previous)
    return code, out.getvalue(), err.getvalue()


def _subprocess(argv: list[str], cwd: Path) -> tuple[int, str, str]:
    kitkb = Path(sys.executable).with_name("kitkb")
    try:
        done = subprocess.run([str(kitkb), *argv], capture_output=True, text=True, errors="replace", cwd=cwd,
                              timeout=TIMEOUT)
    except subprocess.TimeoutExpired:
        return HANG, "", ""
    return done.returncode, done.stdout, done.stderr


def error_lines(stderr: str) -> list[str]:
    """The lines of ``stderr`` that are not warnings nor the success line."""
    return [line for line in stderr.splitlines()
            if line.strip() and "warning:" not in line and not line.startswith("kitkb: wrote")
            and not line.startswith("kitkb: loaded")]


def run_case(case: Case, mutant: bytes, mutation: str, seeds: dict[str, Path], work: Path,
             real_process: bool = False) -> Outcome:
    """Run ``case`` on ``mutant`` in a fresh folder under ``work``; the outcome and its problems."""
    folder = Path(tempfile.mkdtemp(prefix="case-", dir=work))
    try:
        given = folder / "in" / seeds[case.role].name
        given.parent.mkdir()
        given.write_bytes(mutant)
        out = folder / "out"
        out.mkdir()
        db = out / "world.sqlite"
        shutil.copyfile(seeds["db"], db)  # a database that exists before the command
        watched = [given, db] + [p for r, p in seeds.items() if r != case.role]
        before = {p: _digest(p) for p in watched}
        argv = case.argv(given, seeds, out)
        start = time.perf_counter()
        code, stdout, stderr = _subprocess(argv, folder) if real_process else _in_process(argv)
        outcome = Outcome(case.name, mutation, code, stderr, time.perf_counter() - start, real=real_process)
        outcome.problems = _problems(outcome, stdout, before, argv, case, folder)
        return outcome
    finally:
        shutil.rmtree(folder, ignore_errors=True)


def _problems(o: Outcome, stdout: str, before: dict[Path, str | None], argv: list[str], case: Case,
              folder: Path) -> list[str]:
    problems = []
    if o.code == HANG:
        problems.append(f"hang (still running after {TIMEOUT} s)")
    elif o.code not in (0, 1, 2):
        problems.append(f"exit {o.code}")
    if "Traceback" in o.stderr or "Traceback" in stdout:
        problems.append("traceback")
    written = Path(argv[argv.index("--db") + 1]) if case.replaces_db and o.code == 0 else None
    errors = error_lines(o.stderr)
    if o.code == 2 and len(errors) != 1:
        problems.append(f"{len(errors)} error lines on exit 2")
    for path, digest in before.items():
        if path == written:
            continue
        if _digest(path) != digest:
            problems.append(f"{path.name} changed")
    if written is not None:
        with contextlib.closing(sqlite3.connect(written)) as con:
            if con.execute("PRAGMA integrity_check").fetchone()[0] != "ok":
                problems.append("database fails integrity_check")
    temps = _temps(folder)
    if temps:
        problems.append(f"temporary files left: {temps}")
    return problems


# --- the campaign --------------------------------------------------------------------------

def campaign(inputs: int, seed: int, work: Path, real: int = 0,
             progress: Callable[[int, Outcome], None] | None = None, budget: float | None = None) -> list[Outcome]:
    """``inputs`` mutants over the cases (by weight), every ``inputs // real``-th of them in a
    subprocess; with ``budget`` (seconds) no new mutant is tried once it is spent."""
    seeds = make_seeds(work / "seeds")
    data = {role: path.read_bytes() for role, path in seeds.items()}
    rng = random.Random(seed)
    weighted = [c for c in CASES for _ in range(c.weight)]
    outcomes = []
    every = max(1, inputs // real) if real else 0
    end = time.monotonic() + budget if budget else None
    for i in range(inputs):
        if end is not None and time.monotonic() > end:
            break
        case = rng.choice(weighted)
        kind = rng.choice(kinds_for(case.role))
        mutant = mutate(data[case.role], kind, rng.randrange, family(case.role))
        outcome = run_case(case, mutant, kind, seeds, work, real_process=bool(every) and i % every == every - 1)
        outcomes.append(outcome)
        if progress:
            progress(i, outcome)
    return outcomes


def summary(outcomes: list[Outcome]) -> dict:
    """Counts: inputs, outcomes by exit code, by command and exit code, problems."""
    by_case: dict[str, Counter] = {}
    for o in outcomes:
        by_case.setdefault(o.case, Counter())[o.code] += 1
    return {
        "inputs": len(outcomes),
        "subprocesses": sum(o.real for o in outcomes),
        "by_exit": dict(sorted(Counter(o.code for o in outcomes).items())),
        "by_case": {k: dict(sorted(v.items())) for k, v in sorted(by_case.items())},
        "by_mutation": dict(sorted(Counter(o.mutation for o in outcomes).items())),
        "tracebacks": sum("traceback" in o.problems for o in outcomes),
        "hangs": sum(o.code == HANG for o in outcomes),
        "problems": [{"case": o.case, "mutation": o.mutation, "code": o.code, "problems": o.problems,
                      "stderr": o.stderr[-500:]} for o in outcomes if o.problems],
        "seconds": round(sum(o.seconds for o in outcomes), 1),
    }


def render(result: dict, seed: int, real: int, wall: float) -> str:
    from common import cpu_model

    codes = sorted({int(c) for v in result["by_case"].values() for c in v})
    head = "| command | inputs | " + " | ".join(f"exit {c}" for c in codes) + " |"
    rows = [head, "|---|---:|" + "---:|" * len(codes)]
    for name, counts in result["by_case"].items():
        counts = {int(k): v for k, v in counts.items()}
        rows.append(f"| `{name}` | {sum(counts.values())} | " + " | ".join(str(counts.get(c, 0)) for c in codes) + " |")
    by_exit = ", ".join(f"exit {c}: {n:,}" for c, n in result["by_exit"].items())
    by_mut = ", ".join(f"{k} {v}" for k, v in result["by_mutation"].items())
    return "\n".join([
        "## Bad-input campaign",
        "",
        "`benchmarks/bench_bad_input.py` (the engine of `tests/test_bad_input.py`): seeds — a generated 3-part "
        "scenario (Turtle, and RDF/XML by `kitkb convert`), NIST's OWL functional syntax states, NIST's CRCL XML "
        "and its CRCL text, generated and NIST PDDL, a world-model SQLite database — mutated (truncated, bytes "
        "flipped, inserted or deleted, lines shuffled or repeated, numbers made NaN / infinite / 1e308 / 400 "
        "digits, huge literals, UTF-16/32, Latin-1 and invalid UTF-8 bytes, empty, random binary, a pose relative "
        "to its own object or below it and object properties pointed at other individuals, nesting up to "
        "200,000 deep, SQLite pages garbled) and given to every command that reads files, in process "
        f"(`kb.cli.main`), one in {max(1, result['inputs'] // max(real, 1))} of them in a real `kitkb` subprocess "
        f"({result.get('subprocesses', real)} in all). Every outcome must be exit 0, 1 or 2 "
        "with one error line, no traceback, every input and the pre-existing database byte-identical, no "
        "temporary file left.",
        "",
        f"- Command: `.venv/bin/python benchmarks/bench_bad_input.py --inputs {result['inputs']} --seed {seed} "
        f"--subprocess {result.get('subprocesses', real)}` (counts in `benchmarks/results/bad_input.json`; the "
        "same checks run under hypothesis in `tests/test_bad_input.py`, a few mutants per command by default "
        "and four times as many in the slow run).",
        f"- Machine: {cpu_model()}, {os.cpu_count()} cores (shared); seed {seed}; {wall:.0f} s wall.",
        f"- **{result['inputs']:,} inputs tried**: {by_exit}; **{result['tracebacks']} tracebacks**, "
        f"{result['hangs']} hangs (over {TIMEOUT} s), {len(result['problems'])} outcomes with a problem.",
        f"- Mutations: {by_mut}.",
        "",
        *rows,
        "",
    ])


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--inputs", type=int, default=3000, help="mutants to try (default 3000)")
    parser.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    parser.add_argument("--subprocess", type=int, default=100, help="of them, run in real subprocesses (default 100)")
    parser.add_argument("--json", default=str(ROOT / "benchmarks" / "results" / "bad_input.json"),
                        help="where the counts go")
    parser.add_argument("--budget", type=float, metavar="SECONDS",
                        help="try no new input after this many seconds (the counts say how many were tried)")
    parser.add_argument("--no-doc", action="store_true", help="do not write docs/benchmarks.md")
    parser.add_argument("--render", action="store_true",
                        help="only rewrite the docs/benchmarks.md section from the --json results")
    args = parser.parse_args(argv)
    from common import write_doc

    if args.render:
        saved = json.loads(Path(args.json).read_text())
        write_doc("Bad-input campaign", render(saved, saved["seed"], saved["subprocess"], saved["wall"]))
        return 0

    start = time.perf_counter()
    cwd = os.getcwd()
    with tempfile.TemporaryDirectory(prefix="kitkb-bad-input-") as tmp:
        work = Path(tmp)
        os.chdir(work)  # planners write their scratch files in the working directory

        def progress(i: int, o: Outcome) -> None:
            if o.problems:
                print(f"[{i}] {o.case} {o.mutation}: exit {o.code} {o.problems} {o.stderr[-300:]!r}", flush=True)
            elif i % 100 == 0:
                print(f"[{i}] ...", flush=True)

        try:
            outcomes = campaign(args.inputs, args.seed, work, args.subprocess, progress, args.budget)
        finally:
            os.chdir(cwd)
    result = summary(outcomes)
    wall = time.perf_counter() - start
    Path(args.json).parent.mkdir(parents=True, exist_ok=True)
    Path(args.json).write_text(json.dumps({"seed": args.seed, "subprocess": args.subprocess, "wall": round(wall, 1),
                                           **result}, indent=1) + "\n")
    if not args.no_doc:
        write_doc("Bad-input campaign", render(result, args.seed, args.subprocess, wall))
    print(json.dumps({k: result[k] for k in ("inputs", "by_exit", "tracebacks")}))
    print(f"{len(result['problems'])} problems")
    return 1 if result["problems"] else 0


if __name__ == "__main__":
    sys.exit(main())
