"""Bad input a fresh user writes: a table whose `type` key is misspelt (`typ = "revolute"`). The error is one line
naming the field and what is missing, with the keys the table does have, so the typo shows (the old message said
`must be one of ..., got None`)."""

from __future__ import annotations

from pathlib import Path

import pytest
from cli_helpers import make_runner, one_line_error
from test_fresh_review_stops import FILE


@pytest.mark.parametrize(("table", "line"), [("joints.A", 'type = "revolute"'), ("loads.unlock", 'type = "moment"')])
def test_misspelt_type_key(tmp_path: Path, table: str, line: str) -> None:
    text = FILE.read_text()
    head = f"[{table}]\n{line}\n"
    assert head in text
    bad = tmp_path / "typo.toml"
    bad.write_text(text.replace(head, f"[{table}]\ntyp{line[4:]}\n"))
    one_line_error(make_runner()("check", bad), f"{table}.type", "missing", "typ,")
