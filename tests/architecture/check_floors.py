#!/usr/bin/env python3
"""Floors that only point down: every #include between core's rooms goes to a lower floor.

The floors are declared once, in docs/architecture.md's "Floors" table (| floor | rooms | ...),
each room a folder of core/formats, core/host or core/apps. A file may include its own room's headers and any
room on a lower floor; an include of a room on its own floor (another room) or a higher one fails,
named as file:line. Every room folder must stand in the table, and every source file of the
host's and the formats' rooms must have its line in the document's room tables (`stem`), so the map stays the
tree. Run by ctest as `floors`; exit 1 with one line per finding, 0 with a summary line.
"""
import re
import sys
from pathlib import Path

ROOT = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(__file__).resolve().parents[2]
DOC = ROOT / "docs" / "architecture.md"
SOURCES = (".cpp", ".hpp", ".h", ".c")
SIDES = ("formats", "host", "apps")  # core's libraries, from the ground up


def floors_table(doc: str) -> dict[str, tuple[int, str]]:
    """room -> (floor, side: one of SIDES) from the '## Floors' section's table."""
    m = re.search(r"^## Floors\b(.*?)(?=^## )", doc, re.S | re.M)
    if not m:
        raise SystemExit(f"{DOC}: no '## Floors' section")
    rooms = {}
    for line in m.group(1).splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) < 2 or not cells[0].isdigit():
            continue
        for room in re.findall(r"`core/(" + "|".join(SIDES) + r")/([a-z_]+)/`", cells[1]):
            rooms[room[1]] = (int(cells[0]), room[0])
    if not rooms:
        raise SystemExit(f"{DOC}: the Floors table names no room (`core/host/ROOM/`)")
    return rooms


def room_of(path: Path) -> str | None:
    rel = path.relative_to(ROOT / "core").parts
    return rel[1] if len(rel) > 2 and rel[0] in SIDES else None


def main() -> int:
    doc = DOC.read_text()
    rooms = floors_table(doc)
    problems = []
    folders = [d for side in SIDES for d in sorted((ROOT / "core" / side).iterdir()) if d.is_dir()]
    for d in folders:
        if d.name not in rooms:
            problems.append(f"{d.relative_to(ROOT)}: a room not on any floor of {DOC.relative_to(ROOT)}'s Floors table")
        elif rooms[d.name][1] != d.parent.name:
            problems.append(f"{d.relative_to(ROOT)}: the Floors table puts it in core/{rooms[d.name][1]}")
    # a room's unit tests (ROOM/tests/) may include any floor, as tests/ does
    files = [f for d in folders for f in sorted(d.rglob("*")) if f.suffix in SOURCES and not {"node_modules", "tests"} & set(f.parts)]
    by_name: dict[str, set[str]] = {}
    for f in files:
        by_name.setdefault(f.name, set()).add(room_of(f))
    count = 0
    for f in files:
        own = room_of(f)
        if own not in rooms:
            continue
        for n, line in enumerate(f.read_text(errors="replace").splitlines(), 1):
            m = re.match(r'\s*#\s*include\s+"([^"]+)"', line)
            if not m:
                continue
            inc = m.group(1)
            first = inc.split("/")[0]
            targets = {first} if "/" in inc and first in rooms else by_name.get(Path(inc).name, set()) - {None}
            if own in targets:
                continue
            for t in targets:
                if t not in rooms:
                    continue
                count += 1
                if rooms[t][0] >= rooms[own][0]:
                    where = "its own floor" if rooms[t][0] == rooms[own][0] else "a higher floor"
                    problems.append(f"{f.relative_to(ROOT)}:{n}: includes \"{inc}\" of room {t}/ on {where} "
                                    f"({rooms[t][0]}; {own}/ is on {rooms[own][0]})")
    for f in files:
        if room_of(f) in rooms and rooms[room_of(f)][1] in ("formats", "host") and f"`{f.stem}`" not in doc:
            problems.append(f"{f.relative_to(ROOT)}: no line for `{f.stem}` in {DOC.relative_to(ROOT)}")
    for p in problems:
        print(p)
    print(f"floors: {len(rooms)} rooms, {len(files)} files, {count} includes between rooms, {len(problems)} going up or unmapped")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
