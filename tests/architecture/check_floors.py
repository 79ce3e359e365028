#!/usr/bin/env python3
"""Floors that only point down, in the whole house: every #include goes to a lower floor.

Two tables of docs/architecture.md declare the floors, and this script reads them:
 * "The house's floors" (| floor | folders | ...): the SDK, the domain floor (sdk/mission,
   sdk/aero), and the plugins and core side by side. A file of one folder may include its own
   folder's files and the public headers (include/) of a folder on a lower floor; a plugin may
   also include another plugin's public headers, never its src/, tools/, tests/ or any header
   outside its include/. core/ and sdk/ never include a file of plugins/, whether by a relative
   path or by a name only a plugin's include directory makes reachable. tests/ and bench/ (the
   top-level folders) may include every floor.
 * "Floors" (| floor | rooms | ...): core's rooms, each a folder of core/formats, core/host or
   core/apps. A room includes its own files and rooms on lower floors; an include of a room on its
   own floor (another room) or a higher one fails. Every room folder must stand in the table.

An include is resolved against where the files are: beside the including file, else in its own
folder (its private include directories), else a folder's public header (FOLDER/include/NAME);
a name found only in another folder's private files is reported as such. Every production source
(.cpp, .hpp, .h, .c outside tests/ and bench/) of core/ must be named (`stem`) on its room's lines of the
"Inside core/..." tables, so the map stays the tree. Run by ctest as `floors`; exit 1 with one
line per finding (file:line), 0 with a summary line.
"""
import re
import sys
from pathlib import Path

ROOT = (Path(sys.argv[1]) if len(sys.argv) > 1 else Path(__file__).parents[2]).resolve()
DOC = ROOT / "docs" / "architecture.md"
SOURCES = (".cpp", ".hpp", ".h", ".c", ".cc")
SIDES = ("formats", "host", "apps")  # core's libraries, from the ground up
SKIP = {"build", ".git", "node_modules"}
FREE = ("tests", "bench")  # top-level folders that may include every floor
INCLUDE = re.compile(r'\s*#\s*include\s+(?:"([^"]+)"|<([^>]+)>)')


def section(doc: str, heading: str) -> str:
    m = re.search(r"^## " + re.escape(heading) + r"\s*$(.*?)(?=^## |\Z)", doc, re.S | re.M)
    if not m:
        raise SystemExit(f"{DOC}: no '## {heading}' section")
    return m.group(1)


def table_rows(text: str):
    """(first cell, second cell, ...) of each table row whose first cell is a number."""
    for line in text.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) >= 2 and cells[0].isdigit():
            yield int(cells[0]), cells[1]


def house_table(doc: str) -> dict[str, int]:
    """folder pattern ('sdk', 'sdk/aero', 'plugins/*', 'core', ...) -> floor."""
    folders = {}
    for floor, cell in table_rows(section(doc, "The house's floors")):
        for f in re.findall(r"`([a-z_]+(?:/(?:[a-z_]+|NAME))?)/`", cell):
            folders[f.replace("NAME", "*")] = floor
    if not folders:
        raise SystemExit(f"{DOC}: the house's floors table names no folder (`sdk/`)")
    return folders


def rooms_table(doc: str) -> dict[str, tuple[int, str]]:
    """room -> (floor, side: one of SIDES) from the '## Floors' section's table."""
    rooms = {}
    for floor, cell in table_rows(section(doc, "Floors")):
        for side, room in re.findall(r"`core/(" + "|".join(SIDES) + r")/([a-z_]+)/`", cell):
            rooms[room] = (floor, side)
    if not rooms:
        raise SystemExit(f"{DOC}: the Floors table names no room (`core/host/ROOM/`)")
    return rooms


def named_files(doc: str) -> dict[tuple[str, str], set[str]]:
    """(side, room) -> every `name` on the room's lines of the 'Inside core/SIDE' tables."""
    named: dict[tuple[str, str], set[str]] = {}
    for side, body in re.findall(r"^## Inside core/([a-z]+)\b[^\n]*\n(.*?)(?=^## |\Z)", doc, re.S | re.M):
        room = None
        for line in body.splitlines():
            cells = [c.strip() for c in line.strip().strip("|").split("|")]
            if not line.startswith("|") or len(cells) < 3:
                continue
            m = re.fullmatch(r"`([a-z_]+)/`", cells[0])
            room = m.group(1) if m else (room if cells[0] == "" else None)
            if room:
                named.setdefault((side, room), set()).update(re.findall(r"`([^`]+)`", cells[1]))
    return named


class House:
    def __init__(self, folders: dict[str, int]):
        self.folders = folders
        self.files = [p for p in self._walk(ROOT) if p.suffix in SOURCES]
        self.by_name: dict[str, list[Path]] = {}
        for p in self.files:
            self.by_name.setdefault(p.name, []).append(p)

    def _walk(self, d: Path):
        for p in sorted(d.iterdir()):
            # (build-fuzz, build-asan, build-tsan: make fuzz's and the sanitizers' trees, .gitignore's /build-*/)
            if p.name in SKIP or p.name.startswith("build-") or p.is_symlink():
                continue
            if p.is_dir():
                yield from self._walk(p)
            elif p.is_file():
                yield p

    def folder_of(self, p: Path) -> str | None:
        """The house's folder of a file ('sdk/aero', 'plugins/sim_aero', 'core', ...), or None (free)."""
        parts = p.relative_to(ROOT).parts
        for n in (2, 1):
            if len(parts) > n:
                key = "/".join(parts[:n])
                wild = "/".join(parts[: n - 1] + ("*",))
                if key in self.folders:
                    return key
                if wild in self.folders:
                    return key
        return None

    def floor(self, folder: str) -> int:
        if folder in self.folders:
            return self.folders[folder]
        return self.folders[folder.split("/")[0] + "/*"]

    def is_plugin(self, folder: str) -> bool:
        return folder.startswith("plugins/")

    def resolve(self, f: Path, inc: str, quoted: bool) -> tuple[Path | None, bool]:
        """(the file an include names, whether it is a public header or the includer's own) or
        (a private file of another folder, False) or (None, True) when the tree has no such file."""
        if quoted and (f.parent / inc).is_file():
            target = (f.parent / inc).resolve()
            return target, self.folder_of(target) == self.folder_of(f) or self._public(target)
        found = [p for p in self.by_name.get(Path(inc).name, []) if p.as_posix().endswith("/" + inc)]
        own = self.folder_of(f)
        for p in found:
            if self.folder_of(p) == own:
                return p, True
        for p in found:
            folder = self.folder_of(p)
            if folder is None or not (ROOT / folder / "include").is_dir() or p == ROOT / folder / "include" / inc:
                return p, True
        return (found[0], False) if found else (None, True)

    def _public(self, p: Path) -> bool:
        """Is p a public header of its folder: in FOLDER/include/ (a folder without one: any file)?"""
        folder = self.folder_of(p)
        return folder is None or not (ROOT / folder / "include").is_dir() or p.is_relative_to(ROOT / folder / "include")


def house_findings(house: House) -> tuple[list[str], int]:
    problems, count = [], 0
    for f in house.files:
        own = house.folder_of(f)
        if own is None:
            continue
        for n, line in enumerate(f.read_text(errors="replace").splitlines(), 1):
            m = INCLUDE.match(line)
            if not m:
                continue
            inc = m.group(1) or m.group(2)
            target, public = house.resolve(f, inc, m.group(1) is not None)
            to = house.folder_of(target) if target else own
            if to == own:
                continue
            count += 1
            where = f"{f.relative_to(ROOT)}:{n}: includes \"{inc}\" ({target.relative_to(ROOT)})"
            if to is None:
                if not {"tests", "bench"} & set(f.relative_to(ROOT).parts):  # tests may share tests/'s helpers
                    problems.append(f"{where}: a file outside the house's floors")
            elif not public:
                problems.append(f"{where}: a private file of {to}/ (only {to}/include/ is public)")
            elif house.is_plugin(to) and not house.is_plugin(own):
                problems.append(f"{where}: {own}/ never includes a plugin's file")
            elif house.floor(to) >= house.floor(own) and not (house.is_plugin(own) and house.is_plugin(to)):
                where_floor = "its own floor" if house.floor(to) == house.floor(own) else "a higher floor"
                problems.append(f"{where}: {to}/ is on {where_floor} ({house.floor(to)}; {own}/ is on {house.floor(own)})")
    return problems, count


def room_of(path: Path) -> str | None:
    rel = path.relative_to(ROOT / "core").parts
    return rel[1] if len(rel) > 2 and rel[0] in SIDES else None


def core_findings(doc: str, rooms: dict[str, tuple[int, str]]) -> tuple[list[str], int, int]:
    problems = []
    folders = [d for side in SIDES for d in sorted((ROOT / "core" / side).iterdir()) if d.is_dir()]
    for d in folders:
        if d.name not in rooms:
            problems.append(f"{d.relative_to(ROOT)}: a room not on any floor of {DOC.relative_to(ROOT)}'s Floors table")
        elif rooms[d.name][1] != d.parent.name:
            problems.append(f"{d.relative_to(ROOT)}: the Floors table puts it in core/{rooms[d.name][1]}")
    # a room's unit tests and benchmarks (ROOM/tests/, ROOM/bench/) may include any floor, as tests/ does
    files = [f for d in folders for f in sorted(d.rglob("*")) if f.suffix in SOURCES and not {"node_modules", "tests", "bench"} & set(f.parts)]
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
    return problems + unnamed_files(doc, files), len(files), count


def unnamed_files(doc: str, files: list[Path]) -> list[str]:
    """A production file of core/ whose stem is not on its room's lines of the document."""
    named, problems = named_files(doc), []
    for f in files:
        side, room = f.relative_to(ROOT / "core").parts[:2]
        if f.stem not in named.get((side, room), set()):
            problems.append(f"{f.relative_to(ROOT)}: no `{f.stem}` on the lines of room {room}/ in "
                            f"{DOC.relative_to(ROOT)} (Inside core/{side})")
    return problems


def main() -> int:
    doc = DOC.read_text()
    house = House(house_table(doc))
    rooms = rooms_table(doc)
    house_problems, house_count = house_findings(house)
    core_problems, core_files, core_count = core_findings(doc, rooms)
    for p in house_problems + core_problems:
        print(p)
    print(f"floors: {len(house.folders)} floors' folders, {len(house.files)} files, {house_count} includes between "
          f"folders; {len(rooms)} rooms of core, {core_files} production files, {core_count} includes between rooms; "
          f"{len(house_problems) + len(core_problems)} going up, across or unmapped")
    return 1 if house_problems or core_problems else 0


if __name__ == "__main__":
    sys.exit(main())
