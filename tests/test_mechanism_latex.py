"""``mechcont equations --latex`` is valid LaTeX: every equation parses as math (matplotlib's
TeX-subset parser), labels have their underscores escaped, braces balance."""

import re

import pytest
from click.testing import CliRunner
from matplotlib.mathtext import MathTextParser

from mechcont.cli._app import _register, cli


@pytest.mark.parametrize("args", [["overcentre"], ["overcentre.toml"], ["fourbar"], ["fivebar", "--reduced"],
                                  ["slidercrank"]])
def test_latex_output_parses(args):
    _register()
    result = CliRunner().invoke(cli, ["equations", *args, "--latex"])
    assert result.exit_code == 0, result.output
    lines = result.output.strip().splitlines()
    assert lines[0] == r"\begin{align}" and lines[-1] == r"\end{align}"
    body = lines[1:-1]
    assert len(body) >= 3
    parser = MathTextParser("path")
    for i, line in enumerate(body):
        assert line.count("{") == line.count("}")
        lhs, rest = line.split("&=", 1)
        parser.parse(f"${lhs}$")  # raises ValueError on malformed math
        labels = re.findall(r"\\text\{([^}]*)\}", rest)
        assert len(labels) == 1 and re.search(r"(?<!\\)_", labels[0]) is None, labels
        assert line.rstrip().endswith(r"\\") == (i < len(body) - 1)
