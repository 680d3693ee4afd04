"""Where a key path is written in a description file's text: errors re-issued with the file name and line."""

from __future__ import annotations

import re

from ..errors import InputError

__all__ = ["locate_error", "key_at"]


def locate_error(source: tuple[str, str] | None, exc: InputError) -> InputError:
    """Re-issue ``exc`` (whose field is a key path) with the file name and line of that key."""
    if source is None or not isinstance(exc, InputError):
        return exc
    filename, text = source
    message = str(exc)[len(exc.field) + 2:]
    line = _line_of(text, exc.field.split("."))
    where = f"{filename}:{line}" if line else filename
    return InputError(f"{where}: {exc.field}", message)


def _split_key(key: str) -> list[str]:
    parts = re.findall(r'"[^"]*"|\'[^\']*\'|[^.\s]+', key)
    return [p.strip("\"'") for p in parts]


def _line_of(text: str, path: list[str]) -> int | None:
    """1-based line of the key ``path`` (e.g. ``["bodies", "1", "mass"]``), best effort."""
    path = [p for p in path if p]
    best_line, best_depth = None, -1
    header: list[str] = []
    header_counts: dict[tuple[str, ...], int] = {}
    for no, raw in enumerate(text.splitlines(), start=1):
        line = raw.split("#", 1)[0].strip()
        m = re.match(r"^\[\[?([^\]]+)\]\]?$", line)
        if m:
            header = _split_key(m.group(1))
            header_counts[tuple(header)] = header_counts.get(tuple(header), 0) + 1
            if header == path[:len(header)] and len(header) > best_depth:
                best_line, best_depth = no, len(header)
            continue
        m = re.match(r"^([^=]+?)\s*=", line)
        if not m:
            continue
        full = header + _split_key(m.group(1))
        depth = 0
        while depth < min(len(full), len(path)) and full[depth] == path[depth]:
            depth += 1
        if depth == len(full) and depth > best_depth:
            best_line, best_depth = no, depth
        # inline tables: the rest of the path appears on this line (points = {spring = [...]})
        if depth == len(full) and depth < len(path) and all(p in raw for p in path[depth:]):
            best_line, best_depth = no, len(path)
    return best_line


def key_at(text: str, line: int) -> str:
    """The table and key written on 1-based ``line`` of ``text`` (for syntax errors)."""
    header = ""
    lines = text.splitlines()
    for raw in lines[:line]:
        s = raw.split("#", 1)[0].strip()
        m = re.match(r"^\[\[?([^\]]+)\]\]?$", s)
        if m:
            header = m.group(1).strip()
    if 0 < line <= len(lines):
        m = re.match(r"^\s*([^=\[]+?)\s*=", lines[line - 1])
        if m:
            return f"{header}.{m.group(1).strip()}" if header else m.group(1).strip()
    return header or "(top level)"
