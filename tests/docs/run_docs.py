#!/usr/bin/env python3
"""The documentation, run as a reader would paste it (issue 63).

    run_docs.py --build BUILD [--update] [--keep] [--keep-going] [--timeout S] DOC...

For each DOC (README.md, docs/tuning.md, ...; `all`: every doc of DOCS below) the ```sh blocks
run in order, in one bash (so `cd`, `export` and variables carry over from block to block, and
`cmd &` is a job of that shell), from the repository root, in a fresh HOME and so a fresh install
prefix (`cmake --install build --prefix ~/tern` goes into that HOME), with the system's PATH and
a clean environment. A block is not run when an HTML comment right before it says
`<!-- not run: why -->`; `<!-- needs: PATH ... -->` skips it (with a SKIP line, not a failure)
when a PATH is missing, and so does a block that names `../shared/reference/...` when that is
missing: the later blocks of its section are skipped with it. The first failing command fails
the document: its file and line, its exit status and the tail of its output. At the end of a
document, background jobs still running get 10 s to end, then are killed (and named).

The repository root the commands see is a copy-free farm, BUILD/docs_test/<doc>/<repo>: a
symbolic link to each of the repository's top-level entries, `build` a link to BUILD (the tree
the doc's `build/bin/tern` and `make build` use), `configs/` a tree of links (files the docs write
into configs/ stay in the farm), and `../shared` a link to the repository's `../shared` when there
is one. So what a doc writes (runs/, logs/, my_ctl/, configs/...) never lands in the repository.
Caches live outside the fresh HOME (XDG_CACHE_HOME, CCACHE_DIR: BUILD/docs_test/cache): ccache is
the compiler launcher of the doc's own CMake projects, matplotlib keeps its font cache. `make` is
run under a lock (flock), so that two documents run at once by ctest never run two `make build`s
in one build tree at the same time.

Then the figures of tests/docs/figures.yaml measured by this document's run are checked: each
is a number the docs write, found by a regex, against the value the run produced (a run's
summary.json, the output of a command, a computed expression), within the written number's
rounding unless a tolerance is given. A mismatch names the file and line, the number written and
the number measured. `--update` writes the measured numbers into the files instead (one command
moves the docs with the code).

Exit status: 0 all passed, 1 a failure, 77 every block of every document skipped.
"""
from __future__ import annotations

import argparse
import csv
import fnmatch
import glob
import json
import math
import os
import re
import shlex
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
SOURCE = HERE.parent.parent
DOCS = [
    "README.md",
    "docs/writing-a-plugin.md",
    "docs/replay-your-own-flight.md",
    "docs/tuning.md",
    "docs/aircraft-modelling.md",
    "docs/flying.md",
    "docs/fly-with-the-real-firmware.md",
    "docs/validate.md",
    "docs/system-identification.md",
    "docs/python.md",
]
MARK = "@@tern-docs"
SYSTEM_PATH = "/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin"
SHADOWED = ["configs"]  # directories the docs write into: a tree of links, not one link


def slug(doc: str) -> str:
    return re.sub(r"[^a-z0-9]+", "_", Path(doc).stem.lower()).strip("_")


# ---------------------------------------------------------------------------------------------
# The document's blocks and commands


class Block:
    def __init__(self, doc, line, text_lines, directives, section):
        self.doc, self.line, self.lines, self.section = doc, line, text_lines, section
        self.not_run = directives.get("not run")
        self.needs = directives.get("needs", "").split()
        self.commands: list[tuple[int, str]] = []  # (line in the doc, command text)


def html_comments_before(lines: list[str], i: int) -> list[str]:
    """The HTML comments right before line i (0-based), nearest last."""
    out, j = [], i - 1
    while j >= 0 and not lines[j].strip():
        j -= 1
    while j >= 0 and lines[j].strip().endswith("-->"):
        k = j
        while k >= 0 and "<!--" not in lines[k]:
            k -= 1
        if k < 0:
            break
        text = " ".join(l.strip() for l in lines[k:j + 1])
        text = text[text.index("<!--") + 4:text.rindex("-->")].strip()
        out.insert(0, text)
        j = k - 1
        while j >= 0 and not lines[j].strip():
            j -= 1
    return out


def parse_directives(comments: list[str]) -> dict:
    d = {}
    for c in comments:
        m = re.match(r"(not run|needs)\s*:\s*(.*)$", c, re.S)
        if m:
            d[m.group(1)] = m.group(2).strip()
    return d


def complete(text: str) -> bool:
    """Whether bash parses `text` as whole commands (not a line continued, an open quote or if)."""
    if text.rstrip().endswith("\\"):
        return False
    # a syntax check needs no sanitizer runtime (a preloaded ThreadSanitizer crashes bash)
    env = {k: v for k, v in os.environ.items() if k != "LD_PRELOAD"}
    r = subprocess.run(["bash", "-n", "-c", text], capture_output=True, text=True, env=env)
    return r.returncode == 0


def split_commands(doc: str, first_line: int, body: list[str]) -> list[tuple[int, str]]:
    cmds, cur, start = [], [], 0
    for k, line in enumerate(body):
        if not cur and (not line.strip() or line.lstrip().startswith("#")):
            continue
        if not cur:
            start = first_line + k
        cur.append(line)
        if complete("\n".join(cur)):
            cmds.append((start, "\n".join(cur)))
            cur = []
    if cur:
        raise SystemExit(f"{doc}:{start}: the ```sh block ends inside a command:\n" + "\n".join(cur))
    return cmds


def parse_doc(doc: str, text: str) -> list[Block]:
    lines = text.split("\n")
    blocks, i, section = [], 0, ""
    fence = re.compile(r"^(\s*)(`{3,}|~{3,})\s*([^\s`]*)\s*$")
    while i < len(lines):
        if lines[i].startswith("#"):
            section = lines[i].lstrip("#").strip()
        m = fence.match(lines[i])
        if not m:
            i += 1
            continue
        indent, ticks, lang = m.group(1), m.group(2), m.group(3)
        j = i + 1
        while j < len(lines) and not (lines[j].strip().startswith(ticks) and lines[j].strip().strip(ticks[0]) == ""):
            j += 1
        if lang == "sh":
            body = [l[len(indent):] if l.startswith(indent) else l for l in lines[i + 1:j]]
            b = Block(doc, i + 1, body, parse_directives(html_comments_before(lines, i)), section)
            if not b.not_run:
                b.commands = split_commands(doc, i + 2, body)
            blocks.append(b)
        i = j + 1
    return blocks


# ---------------------------------------------------------------------------------------------
# The working directory: a copy-free farm of the repository, a fresh HOME


def tracked_top_level(source: Path) -> list[str]:
    try:
        out = subprocess.run(["git", "-C", str(source), "ls-files", "-z"], capture_output=True, check=True).stdout
        names = sorted({p.split("/", 1)[0] for p in out.decode().split("\0") if p})
        return [n for n in names if (source / n).exists()]
    except (OSError, subprocess.CalledProcessError):
        return sorted(n for n in os.listdir(source) if n not in ("build", "runs", "logs", ".git"))


def shadow(src: Path, dst: Path):
    dst.mkdir()
    for e in sorted(src.iterdir()):
        if e.is_dir() and not e.is_symlink():
            shadow(e, dst / e.name)
        else:
            (dst / e.name).symlink_to(e)


def make_farm(work: Path, source: Path, build: Path, with_shared: bool = True) -> Path:
    farm = work / source.name
    farm.mkdir(parents=True)
    for name in tracked_top_level(source):
        if name == "build":
            continue
        if name in SHADOWED and (source / name).is_dir():
            shadow(source / name, farm / name)
        else:
            (farm / name).symlink_to(source / name)
    (farm / "build").symlink_to(build)
    shared = (source / ".." / "shared").resolve()
    if shared.is_dir() and with_shared:
        (work / "shared").symlink_to(shared)
    return farm


def environment(home: Path, cache: Path, lock: Path) -> dict:
    env = {"HOME": str(home), "PATH": SYSTEM_PATH, "LANG": "C.UTF-8", "LC_ALL": "C.UTF-8", "TERM": "dumb",
           "SHELL": "/bin/bash", "XDG_CACHE_HOME": str(cache), "MPLBACKEND": "Agg",
           "CCACHE_DIR": str(cache / "ccache"), "CCACHE_BASEDIR": str(cache.parent), "CCACHE_NOHASHDIR": "1",
           "TERN_DOCS_MAKE_LOCK": str(lock)}
    # (LD_PRELOAD and the sanitizers' options: only a sanitizer build's tests set them, for the
    # Python that imports its instrumented module: tests/CMakeLists.txt, TERN_SANITIZER_PYTHON_ENV)
    for k in ("USER", "LOGNAME", "TMPDIR", "TZ", "LD_PRELOAD", "ASAN_OPTIONS", "UBSAN_OPTIONS", "LSAN_OPTIONS"):
        if k in os.environ:
            env[k] = os.environ[k]
    if shutil.which("ccache"):
        env["CMAKE_CXX_COMPILER_LAUNCHER"] = "ccache"  # the doc's own CMake projects (CMake >= 3.17)
    return env


# ---------------------------------------------------------------------------------------------
# The script bash runs


PRELUDE = r"""
set -m
__tern_docs_fail=0
__tern_docs_bg=()
# two documents run at once (ctest -j) never run two `make build`s in one tree together
make() { flock "$TERN_DOCS_MAKE_LOCK" make "$@"; }
__tern_docs_end() {
  printf '\n%(mark)s end %%s\n' "$EPOCHREALTIME"
  local i p rc left=""
  for i in $(seq 100); do [ -z "$(jobs -pr)" ] && break; sleep 0.1; done
  for p in $(jobs -pr); do left="$left $p"; done
  if [ -n "$left" ]; then
    printf '\n%(mark)s leftover %%s\n' "$(jobs -l | grep -v -e Done -e Exit | tr -s ' \n' '  ')"
    for p in $left; do kill -TERM -- "-$p" 2>/dev/null || kill -TERM "$p" 2>/dev/null; done
    for i in $(seq 50); do [ -z "$(jobs -pr)" ] && break; sleep 0.1; done
    for p in $(jobs -pr); do kill -KILL -- "-$p" 2>/dev/null || kill -KILL "$p" 2>/dev/null; done
  fi
  for p in "${__tern_docs_bg[@]}"; do
    case " $left " in *" ${p%%%%:*} "*) continue ;; esac
    wait "${p%%%%:*}"; rc=$?
    if [ "$rc" -ne 0 ] && [ "$rc" -lt 127 ]; then   # not: unknown to wait (127), ended by a signal (128+)
      printf '\n%(mark)s bgexit %%s %%s\n' "${p#*:}" "$rc"; __tern_docs_fail=1
    fi
  done
  wait 2>/dev/null
  exit "$__tern_docs_fail"
}
"""

COMMAND = r"""
printf '\n%(mark)s run %(line)d %%s\n' "$EPOCHREALTIME"
eval %(text)s
__tern_docs_rc=$?
%(bg)s
if [ "$__tern_docs_rc" -ne 0 ]; then
  printf '\n%(mark)s exit %(line)d %%s %%s\n' "$__tern_docs_rc" "$EPOCHREALTIME"; __tern_docs_fail=1; %(stop)s
fi
"""


def script_for(blocks: list[Block], start: Path, keep_going: bool, skipped_lines: set) -> str:
    out = [PRELUDE % {"mark": MARK}, f"cd {shlex.quote(str(start))} || exit 1"]
    for b in blocks:
        for line, text in b.commands:
            if line in skipped_lines:
                continue
            bg = ""
            if re.search(r"(^|[^&])&\s*(#.*)?$", text.rstrip()):
                bg = f'__tern_docs_bg+=("$!:{line}")'
            out.append(COMMAND % {"mark": MARK, "line": line, "text": shlex.quote(text), "bg": bg,
                                  "stop": ":" if keep_going else "__tern_docs_end"})
    out.append("__tern_docs_end")
    return "\n".join(out) + "\n"


def session_pids(sid: int) -> list[int]:
    pids = []
    for d in os.listdir("/proc"):
        if d.isdigit():
            try:
                with open(f"/proc/{d}/stat") as f:
                    fields = f.read().rsplit(")", 1)[1].split()
                if int(fields[3]) == sid and int(d) != sid:
                    pids.append(int(d))
            except (OSError, IndexError, ValueError):
                pass
    return pids


def kill_session(sid: int):
    for sig in (signal.SIGTERM, signal.SIGKILL):
        pids = session_pids(sid)
        if not pids:
            return
        for p in pids:
            try:
                os.kill(p, sig)
            except OSError:
                pass
        time.sleep(1.0)


# ---------------------------------------------------------------------------------------------
# Running one document


class Result:
    def __init__(self, doc):
        self.doc = doc
        self.failures: list[str] = []
        self.skips: list[str] = []
        self.notes: list[str] = []
        self.ran = 0
        self.log = ""
        self.clean_log = ""
        self.command_failed = False
        self.outputs: dict[int, str] = {}  # command line -> its output
        self.work: Path | None = None
        self.farm: Path | None = None
        self.home: Path | None = None


def shared_reference_paths(text: str) -> list[str]:
    return re.findall(r"\.\./shared/reference[^\s\"'`)]*", text)


def run_doc(doc: str, args, cmd_text: dict) -> Result:
    res = Result(doc)
    text = (args.source / doc).read_text()
    blocks = parse_doc(doc, text)
    work = args.build / "docs_test" / slug(doc)
    res.work = work
    if not args.reuse:
        if work.exists():
            shutil.rmtree(work)
        work.mkdir(parents=True)
    cache = args.build / "docs_test" / "cache"
    cache.mkdir(parents=True, exist_ok=True)
    home = work / "home"
    if args.reuse:
        farm = work / args.source.name
    else:
        home.mkdir()
        farm = make_farm(work, args.source, args.build, not args.without_shared)
    res.farm, res.home = farm, home

    skipped_lines, skip_section = set(), None
    for b in blocks:
        for line, t in b.commands:
            cmd_text[(doc, line)] = t
        if b.not_run:
            continue
        missing = [p for p in b.needs if not (farm / p).exists()]
        missing += [p for p in shared_reference_paths("\n".join(b.lines)) if not (farm / p).exists()]
        if skip_section is not None and b.section == skip_section:
            missing = missing or ["(an earlier block of this section was skipped)"]
        if missing:
            skip_section = b.section
            res.skips.append(f"SKIP {doc}:{b.line}: needs {', '.join(missing)} (absent): {len(b.commands)} command(s) not run")
            skipped_lines.update(l for l, _ in b.commands)
    runnable = [(l, t) for b in blocks for l, t in b.commands if l not in skipped_lines]
    res.ran = len(runnable)
    for s in res.skips:
        print(s, flush=True)
    if args.reuse:
        logf = work / "output.log"
        res.log = logf.read_text(errors="replace") if logf.exists() else ""
        split_output(res, cmd_text)
        return res
    if not runnable:
        if not any(b.commands for b in blocks):
            res.failures.append(f"FAIL {doc}: no ```sh block with a command to run (its commands in ```sh blocks, "
                                f"or <!-- not run: why --> before each)")
        return res

    script = work / "doc.sh"
    script.write_text(script_for(blocks, farm, args.keep_going, skipped_lines))
    logf = work / "output.log"
    env = environment(home, cache, args.build / "docs_test" / "make.lock")
    print(f"== {doc}: {len(runnable)} commands from {farm} (HOME={home})", flush=True)
    t0 = time.monotonic()
    with open(logf, "wb") as log:
        p = subprocess.Popen(["bash", str(script)], cwd=farm, env=env, stdin=subprocess.DEVNULL,
                             stdout=log, stderr=subprocess.STDOUT, start_new_session=True)
        seen, timed_out, current = 0, False, None
        while True:
            try:
                p.wait(timeout=0.25)
                done = True
            except subprocess.TimeoutExpired:
                done = False
            data = logf.read_bytes()[seen:]
            nl = data.rfind(b"\n")
            if nl >= 0:
                for raw in data[:nl + 1].decode(errors="replace").split("\n"):
                    current = progress(doc, raw, current, cmd_text)
                seen += nl + 1
            if done:
                break
            if time.monotonic() - t0 > args.timeout:
                timed_out = True
                os.killpg(p.pid, signal.SIGTERM)
                try:
                    p.wait(timeout=5)
                except subprocess.TimeoutExpired:
                    os.killpg(p.pid, signal.SIGKILL)
                    p.wait()
                break
        kill_session(p.pid)
    res.log = logf.read_text(errors="replace")
    split_output(res, cmd_text)
    if timed_out:
        line = current[0] if current else 0
        res.failures.append(fail_text(doc, line, cmd_text, f"still running after the document's {args.timeout:.0f} s",
                                      res.outputs.get(line, "")))
    for m in re.finditer(rf"^{MARK} exit (\d+) (\d+) ", res.log, re.M):
        line, rc = int(m.group(1)), int(m.group(2))
        res.failures.append(fail_text(doc, line, cmd_text, f"exited {rc}", res.outputs.get(line, "")))
    for m in re.finditer(rf"^{MARK} bgexit (\d+) (\d+)", res.log, re.M):
        line, rc = int(m.group(1)), int(m.group(2))
        res.failures.append(fail_text(doc, line, cmd_text, f"(in the background) exited {rc}", res.outputs.get(line, "")))
    for m in re.finditer(rf"^{MARK} leftover (.*)$", res.log, re.M):
        res.notes.append(f"NOTE {doc}: still running at the end of the document, killed: {m.group(1).strip()}")
    if not timed_out and p.returncode not in (0, 1):
        res.failures.append(f"FAIL {doc}: bash ended with status {p.returncode} (see {logf})")
    res.command_failed = bool(res.failures)
    print(f"== {doc}: {time.monotonic() - t0:.1f} s", flush=True)
    return res


def progress(doc, raw, current, cmd_text):
    m = re.match(rf"^{MARK} (run|exit|end) (\S+)(?: (\S+))?(?: (\S+))?", raw)
    if not m:
        return current
    now = None
    if m.group(1) == "run":
        now = (int(m.group(2)), float(m.group(3)))
    stamp = float(m.group(3)) if m.group(1) == "run" else (float(m.group(4)) if m.group(1) == "exit" else float(m.group(2)))
    if current:
        line, t = current
        first = cmd_text.get((doc, line), "").split("\n")[0]
        status = "FAILED" if m.group(1) == "exit" else "ok"
        print(f"   {doc}:{line}  {first[:90]}  {status} ({stamp - t:.1f} s)", flush=True)
    return now


def split_output(res: Result, cmd_text):
    """Each command's output: the log between its `run` mark and the next mark."""
    parts = re.split(rf"^{MARK} (.*)\n?", res.log, flags=re.M)
    # parts: [before, mark1, text1, mark2, text2, ...]
    for k in range(1, len(parts) - 1, 2):
        m = re.match(r"run (\d+)", parts[k])
        if m:
            res.outputs[int(m.group(1))] = parts[k + 1].strip("\n")
    res.clean_log = re.sub(rf"^{MARK} .*\n?", "", res.log, flags=re.M)


def fail_text(doc, line, cmd_text, what, output, tail=40):
    cmd = cmd_text.get((doc, line), "?")
    lines = output.split("\n")
    shown = "\n".join("  | " + l for l in lines[-tail:])
    more = f" (last {tail} of {len(lines)} lines)" if len(lines) > tail else ""
    return f"FAIL {doc}:{line}: `{cmd}` {what}\n  output{more}:\n{shown}"


# ---------------------------------------------------------------------------------------------
# Figures


def load_figures(path: Path) -> list[dict]:
    import yaml  # python3-yaml (make deps installs it)

    figs = yaml.safe_load(path.read_text()) or []
    for k, f in enumerate(figs):
        for key in ("file", "text"):
            if key not in f:
                raise SystemExit(f"{path}: entry {k + 1}: no '{key}'")
        f.setdefault("run", f["file"])
        if not any(key in f for key in ("measured", "not_checked")):
            raise SystemExit(f"{path}: entry {k + 1} ({f['file']}: {f['text']}): neither 'measured' nor 'not_checked'")
    return figs


def newest(pattern: str, base: Path, home: Path, pick: str = "newest") -> Path:
    """The newest match of a glob (relative to base, or ~/... in home), or with pick: "first" the
    first in name order (a run directory's name starts with its UTC time: the first flight)."""
    pat = pattern.replace("~", str(home), 1) if pattern.startswith("~") else str(base / pattern)
    hits = glob.glob(pat)
    if not hits:
        raise LookupError(f"nothing matches {pattern}")
    if pick == "first":
        return Path(sorted(hits)[0])
    return Path(max(hits, key=lambda h: os.path.getmtime(h)))


def get_path(obj, path: str):
    """a.b[2].c, list filters [key=value] (the first element whose key equals value)."""
    for tok in re.findall(r"[^.\[\]]+|\[[^\]]*\]", path):
        if tok.startswith("["):
            inner = tok[1:-1]
            if "=" in inner:
                k, v = inner.split("=", 1)
                matches = [e for e in obj if str(e.get(k)) == v]
                if not matches:
                    raise LookupError(f"no element with {k}={v} in {path}")
                obj = matches[0]
            else:
                obj = obj[int(inner)]
        else:
            if tok not in obj:
                raise LookupError(f"no '{tok}' in {path}")
            obj = obj[tok]
    return obj


class Measure:
    """Where a figure's true value comes from, in one document's finished run."""

    def __init__(self, res: Result, cmd_text, build: Path):
        self.res, self.cmd_text, self.build = res, cmd_text, build

    def output_of(self, after: str | None) -> str:
        if not after:
            return self.res.clean_log
        for (doc, line), t in sorted(self.cmd_text.items(), key=lambda x: x[0][1]):
            if doc == self.res.doc and after in t and line in self.res.outputs:
                return self.res.outputs[line]
        raise LookupError(f"no command containing '{after}' ran")

    def summary(self, pattern: str, pick: str = "newest"):
        return json.loads(newest(pattern, self.res.farm, self.res.home, pick).read_text())

    def table(self, pattern: str) -> dict:
        """A CSV table's columns by name (without the unit), as floats."""
        with open(newest(pattern, self.res.farm, self.res.home)) as f:
            rows = list(csv.reader(f))
        names = [re.sub(r"\s*\[.*\]$", "", h).strip() for h in rows[0]]
        cols = {n: [] for n in names}
        for r in rows[1:]:
            if len(r) != len(names):
                continue
            for n, v in zip(names, r):
                try:
                    cols[n].append(float(v))
                except ValueError:
                    cols[n].append(float("nan"))
        return cols

    def columns(self, path: Path, names: list[str]) -> dict:
        """Some columns of a CSV table (headers "name [unit]"), as floats."""
        with open(path) as f:
            r = csv.reader(f)
            head = [re.sub(r"\s*\[.*\]$", "", h).strip() for h in next(r)]
            idx = [head.index(n) for n in names]
            cols = {n: [] for n in names}
            for row in r:
                if len(row) != len(head):
                    continue
                for n, i in zip(names, idx):
                    try:
                        cols[n].append(float(row[i]))
                    except ValueError:
                        cols[n].append(float("nan"))
        return cols

    def altitude_offset(self, run_glob: str, q: float, t0="window", t1="approach") -> float:
        """The q-th percentile of true minus estimated altitude between t0 and t1 (seconds, a
        phase's name: its start, or "window": the metrics window's start), the truth moved into
        the estimator's frame as tern plot draws it (their origins' altitudes apart)."""
        run = newest(run_glob, self.res.farm, self.res.home)
        summ = json.loads((run / "summary.json").read_text())

        def when(x):
            if isinstance(x, (int, float)):
                return float(x)
            if x == "window":
                return float(summ["metrics"]["window_start_s"])
            return float(get_path(summ, f"phases[phase={x}].start_s"))

        lo, hi = when(t0), when(t1)
        topics = run / "topics"
        if not (topics / "state.csv").exists() and (run / "flight.mcap").exists():
            topics = self.res.work / "exported" / run.name  # an MCAP-only run (make fly's): its tables
            if not (topics / "state.csv").exists():
                subprocess.run([str(self.build / "bin" / "tern"), "export", "csv", str(run), "--out", str(topics)],
                               check=True, capture_output=True)
        st = self.columns(topics / "state.csv", ["t", "p_d", "origin_alt", "origin_valid"])
        tr = self.columns(topics / "truth.csv", ["t", "p_d", "origin_alt"])
        valid = [k for k, v in enumerate(st["origin_valid"]) if v > 0.5]
        shift = st["origin_alt"][valid[-1]] - tr["origin_alt"][-1]  # the estimator's origin above the truth's
        out, j = [], 0
        ts, tt = st["t"], tr["t"]
        for k, t in enumerate(ts):
            if t < lo or t > hi:
                continue
            while j + 1 < len(tt) and tt[j + 1] <= t:
                j += 1
            if j + 1 >= len(tt) or tt[j] > t:
                continue
            w = (t - tt[j]) / (tt[j + 1] - tt[j]) if tt[j + 1] > tt[j] else 0.0
            h_true = -(tr["p_d"][j] + w * (tr["p_d"][j + 1] - tr["p_d"][j])) - shift
            out.append(h_true - (-st["p_d"][k]))
        return percentile(out, q)

    def grab(self, regex: str, after: str | None = None) -> float:
        """The number regex's first group matches in the output (of the first command containing after)."""
        m = re.search(regex, self.output_of(after), re.M)
        if not m:
            raise LookupError(f"/{regex}/ not in the output" + (f" of `{after}`" if after else ""))
        return float(m.group(1))

    def yaml_file(self, pattern: str):
        import yaml

        return yaml.safe_load(newest(pattern, self.res.farm, self.res.home).read_text())

    def values(self, spec, doc_regex: str, n: int) -> list[float]:
        if "output" in spec:
            rx = doc_regex if spec["output"] == "same" else spec["output"]
            text = self.output_of(spec.get("after"))
            m = re.search(rx, text, re.M)
            if not m:
                raise LookupError(f"/{rx}/ not in the output" + (f" of `{spec['after']}`" if spec.get("after") else ""))
            vals = [float(g) for g in m.groups()]
            if "groups" in spec:  # the output's groups in another order than the doc's
                vals = [vals[k - 1] for k in spec["groups"]]
        elif "json" in spec:
            obj = self.summary(spec["json"], spec.get("pick", "newest"))
            paths = spec["path"] if isinstance(spec["path"], list) else [spec["path"]]
            vals = [float(get_path(obj, p)) for p in paths]
        elif "expr" in spec:
            ns = {"summary": self.summary, "table": self.table, "get": get_path, "math": math,
                  "output": self.output_of, "size_mb": lambda p: dir_size(newest(p, self.res.farm, self.res.home)) / 1e6,
                  "percentile": percentile, "mean": lambda x: sum(x) / len(x),
                  "altitude_offset": self.altitude_offset, "grab": self.grab, "yaml_file": self.yaml_file,
                  "second_order_step": second_order_step}
            v = eval(spec["expr"], ns)  # the table is the project's own file
            vals = [float(x) for x in (v if isinstance(v, (list, tuple)) else [v])]
        else:
            raise LookupError(f"unknown source {spec}")
        if len(vals) != n:
            raise LookupError(f"{len(vals)} measured values for {n} written")
        return [v * spec.get("scale", 1.0) for v in vals]


def second_order_step(wn: float, zeta: float) -> tuple[float, float]:
    """The unit step response of wn^2 / (s^2 + 2 zeta wn s + wn^2), 0 < zeta < 1: its 10-90 % rise
    time (s) and its overshoot (%)."""
    wd = wn * math.sqrt(1 - zeta * zeta)
    phase = math.acos(zeta)

    def y(t):
        return 1 - math.exp(-zeta * wn * t) / math.sqrt(1 - zeta * zeta) * math.sin(wd * t + phase)

    dt, t, t10, t90 = 1e-4 / wn, 0.0, None, None
    while t90 is None:
        t += dt
        v = y(t)
        if t10 is None and v >= 0.1:
            t10 = t
        if v >= 0.9:
            t90 = t
    return t90 - t10, 100 * math.exp(-zeta * math.pi / math.sqrt(1 - zeta * zeta))


def dir_size(p: Path) -> int:
    if p.is_file():
        return p.stat().st_size
    return sum(f.stat().st_size for f in p.rglob("*") if f.is_file() and not f.is_symlink())


def percentile(xs, q):
    xs = sorted(x for x in xs if not math.isnan(x))
    if not xs:
        return float("nan")
    pos = (len(xs) - 1) * q / 100.0
    lo = int(math.floor(pos))
    hi = min(lo + 1, len(xs) - 1)
    return xs[lo] + (xs[hi] - xs[lo]) * (pos - lo)


def decimals(s: str) -> int:
    return len(s.split(".", 1)[1]) if "." in s else 0


def formatted(v: float, written: str) -> str:
    d = decimals(written)
    out = f"{v:.{d}f}"
    if out.startswith("-") and float(out) == 0:
        out = out[1:]
    if written.startswith("+") and not out.startswith("-"):
        out = "+" + out
    return out


def check_figures(res: Result, figures: list[dict], args, cmd_text, updates: dict) -> None:
    measure = Measure(res, cmd_text, args.build)
    for f in figures:
        if f["run"] != res.doc:
            continue
        path = args.source / f["file"]
        text = path.read_text()
        hits = list(re.finditer(f["text"], text, re.M))
        where = f"{f['file']}: /{f['text']}/"
        if len(hits) != 1:
            res.failures.append(f"FAIL figure {where}: {len(hits)} matches in the file (figures.yaml wants exactly one)")
            continue
        m = hits[0]
        line = text.count("\n", 0, m.start()) + 1
        if "not_checked" in f:
            continue
        n = len(m.groups())
        try:
            vals = measure.values(f["measured"], f["text"], n)
        except (LookupError, OSError, KeyError, ValueError, TypeError, ZeroDivisionError,
                subprocess.CalledProcessError) as e:
            if res.skips:  # what measures it may be in a skipped block
                res.notes.append(f"SKIP figure {f['file']}:{line}: not measured (blocks were skipped): {e}")
            elif res.command_failed and not args.keep_going:  # the run stopped early: that failure says it
                res.notes.append(f"NOTE figure {f['file']}:{line}: not measured (the run stopped early): {e}")
            else:
                res.failures.append(f"FAIL figure {f['file']}:{line}: not measured: {e}")
            continue
        for g in range(1, n + 1):
            written, meas = m.group(g), vals[g - 1]
            gline = text.count("\n", 0, m.start(g)) + 1
            tol = f.get("tolerance")
            if tol is None:
                tol = 0.5 * 10 ** -decimals(written)
            elif isinstance(tol, str) and tol.endswith("%"):
                tol = abs(meas) * float(tol[:-1]) / 100
            bound = f.get("check", "equal")
            wv = float(written)
            ok = (meas >= wv - 1e-12) if bound == "at_least" else (abs(wv - meas) <= float(tol) + 1e-9 * max(1, abs(meas)))
            if ok:
                continue
            if args.update and bound == "equal":
                updates.setdefault(f["file"], []).append((m.start(g), m.end(g), written, formatted(meas, written), gline))
            elif args.update:
                res.failures.append(f"FAIL figure {f['file']}:{gline}: {written} written, {meas:g} measured: a lower bound, not updated by --update")
            else:
                res.failures.append(f"FAIL figure {f['file']}:{gline}: {written} written, {formatted(meas, written)} measured ({meas:.6g})"
                                    f" ({'at least' if bound == 'at_least' else f'tolerance {float(tol):g}'};"
                                    f" {f.get('what', '')}{'; ' if f.get('what') else ''}run_docs.py --update writes it)")


def apply_updates(source: Path, updates: dict):
    for file, edits in updates.items():
        path = source / file
        text = path.read_text()
        for start, end, old, new, line in sorted(set(edits), reverse=True):
            if text[start:end] != old:
                print(f"UPDATE {file}:{line}: changed under us, not updated ({old})")
                continue
            text = text[:start] + new + text[end:]
            print(f"UPDATE {file}:{line}: {old} -> {new}")
        path.write_text(text)


# ---------------------------------------------------------------------------------------------


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("docs", nargs="+", help="README.md, docs/tuning.md, ... or all")
    ap.add_argument("--build", required=True, type=Path, help="the built tree (the doc's build/)")
    ap.add_argument("--source", type=Path, default=SOURCE, help="the repository (default: this file's)")
    ap.add_argument("--figures", type=Path, default=HERE / "figures.yaml")
    ap.add_argument("--update", action="store_true", help="write the measured figures into the docs")
    ap.add_argument("--keep", action="store_true", help="keep BUILD/docs_test/<doc> after a success too")
    ap.add_argument("--keep-going", action="store_true", help="run every command after a failing one too")
    ap.add_argument("--reuse", action="store_true", help="do not run: check the figures on a kept run")
    ap.add_argument("--timeout", type=float, default=900.0, help="seconds per document (default 900)")
    ap.add_argument("--list", action="store_true", help="print the commands that would run, and exit")
    ap.add_argument("--without-shared", action="store_true",
                    help="run as on a machine without ../shared (the steps that need it are skipped)")
    args = ap.parse_args()
    args.build = args.build.resolve()
    args.source = args.source.resolve()
    docs = DOCS if args.docs == ["all"] else args.docs
    for d in docs:
        if not (args.source / d).is_file():
            ap.error(f"no document {d}")
    if args.list:
        for d in docs:
            for b in parse_doc(d, (args.source / d).read_text()):
                if b.not_run:
                    print(f"{d}:{b.line}: not run: {b.not_run}")
                for line, t in b.commands:
                    print(f"{d}:{line}: {t}")
        return 0
    if not (args.build / "bin" / "tern").exists():
        print(f"FAIL: {args.build}/bin/tern is not built", flush=True)
        return 1
    figures = load_figures(args.figures)
    cmd_text: dict = {}
    updates: dict = {}
    failed, ran = False, 0
    for d in docs:
        res = run_doc(d, args, cmd_text)
        ran += res.ran
        check_figures(res, figures, args, cmd_text, updates)
        for n in res.notes:
            print(n)
        for f in res.failures:
            print(f, flush=True)
        if res.failures:
            failed = True
            print(f"== {d}: FAILED; kept {res.work} (output.log: everything it printed)")
        elif res.ran and not args.keep and not args.reuse:
            shutil.rmtree(res.work, ignore_errors=True)
        if not res.failures:
            print(f"== {d}: passed ({res.ran} commands, {len(res.skips)} blocks skipped)")
    if updates:
        apply_updates(args.source, updates)
    if failed:
        return 1
    return 0 if ran else 77


if __name__ == "__main__":
    sys.exit(main())
