"""``oocyte_fe.io.columns.read_columns``: a bad cell is named by the file's own line number."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from oocyte_fe.errors import InputError
from oocyte_fe.io.columns import read_columns


def test_a_bad_cell_names_the_line_of_the_file_below_comments_and_blank_lines(
    tmp_path: Path,
) -> None:
    """Comment and blank lines were dropped before counting, so a NaN on the file's line 6
    was reported on "line 4"; the line is now the file's."""
    path = tmp_path / "t.csv"
    path.write_text("# source: a table\n# units: s, Pa\na,b\n1,2\n\n3,nan\n")
    with pytest.raises(InputError, match=r"t\.csv: b \(line 6\): expected a finite number"):
        read_columns(path)
    path.write_text("# c\na,b\n1,2\n3\n")
    with pytest.raises(InputError, match=r"t\.csv: line 4: expected 2 comma-separated values"):
        read_columns(path)
    path.write_text("# c\na, b\n1,2\n\n3,4\n")
    got = read_columns(path)
    np.testing.assert_array_equal(got["a"], [1.0, 3.0])
    np.testing.assert_array_equal(got["b"], [2.0, 4.0])


def test_tab_and_semicolon_tables_with_decimal_commas_read_as_the_csv(tmp_path: Path) -> None:
    """A spreadsheet's TSV and a European semicolon export (decimal commas) of the same
    table give the CSV's columns exactly; a short row names its separator."""
    rows = [("x_um", "t_kPa"), ("0.5", "-1.25"), ("1e-3", "2")]
    texts = {
        "csv": "\n".join(",".join(r) for r in rows),
        "tsv": "\n".join("\t".join(r) for r in rows),
        "semi": "\n".join(";".join(c.replace(".", ",") for c in r) for r in rows),
    }
    got = {}
    for name, text in texts.items():
        (tmp_path / name).write_text("# a comment\n" + text + "\n")
        got[name] = read_columns(tmp_path / name)
    for name in ("tsv", "semi"):
        assert got[name].keys() == got["csv"].keys()
        for key in got["csv"]:
            np.testing.assert_array_equal(got[name][key], got["csv"][key])
    (tmp_path / "short").write_text("a;b\n1;2\n3\n")
    with pytest.raises(InputError, match=r"line 3: expected 2 semicolon-separated values"):
        read_columns(tmp_path / "short")
