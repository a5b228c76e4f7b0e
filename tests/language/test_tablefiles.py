"""Tables read from files as the MSL reads them (acausal.tablefiles): the MSL 4.1.0 table
files in every format, modelica:// resolution, round trips and every error on small files.

Expected values come from outside the code under test: the MSL files are read again
with scipy.io / h5py directly or parsed by hand here, and the formats are checked
against each other (the MSL wrote the same data into each of them)."""

from __future__ import annotations

import os
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from library_checks import msl_resources
import scipy.io
import scipy.sparse

from acausal import tablefiles
from acausal.errors import ParameterError, TableError
from acausal.tablefiles import load_resource, modelica_path, read_table, register_usertab, usertab

MSL_ROOT = msl_resources()
TABLES = MSL_ROOT / "Modelica" / "Resources" / "Data" / "Tables"
TEST_TABLES = MSL_ROOT / "ModelicaTest" / "Resources" / "Data" / "Tables"
URI = "modelica://Modelica/Resources/Data/Tables/"
TEST_URI = "modelica://ModelicaTest/Resources/Data/Tables/"

#: the MSL text file's table tab1, written there with two rows on one line and a row
#: split over two lines, among comments and blank lines (ModelicaTest's reference)
TAB1 = [[0, 0], [1, 0], [1, 1], [2, 4], [3, 9], [4, 16]]


@pytest.fixture
def msl(monkeypatch):
    """MODELICAPATH = the MSL 4.1.0 resources (skip when they are not on this machine)."""
    if not TABLES.is_dir() or not TEST_TABLES.is_dir():
        pytest.skip(f"the MSL 4.1.0 table files are not in {MSL_ROOT}")
    monkeypatch.setenv("MODELICAPATH", str(MSL_ROOT))
    return MSL_ROOT


def hand_parsed(path: Path, name: str) -> np.ndarray:
    """A matrix of an MSL text file whose rows are one per line, parsed here by hand."""
    lines = path.read_text(encoding="utf-8-sig").split("\n")
    start = next(i for i, line in enumerate(lines) if line.split("(")[0].split() == ["double", name])
    rows, cols = (int(n) for n in lines[start].split("(")[1].split(")")[0].split(","))
    body = [line.split("#")[0].split() for line in lines[start + 1:start + 1 + rows]]
    assert all(len(row) == cols for row in body)
    return np.array(body, dtype=float)


def write(path: Path, text: str) -> str:
    path.write_text(text, encoding="utf-8")
    return str(path)


def message(excinfo) -> str:
    return str(excinfo.value)


# ---------------------------------------------------------------------------
# The MSL 4.1.0 table files
# ---------------------------------------------------------------------------

def test_matrix_a_is_the_same_in_the_text_file_and_every_mat_version(msl):
    h5py = pytest.importorskip("h5py")
    by_hand = hand_parsed(TABLES / "test.txt", "a")
    assert by_hand.shape == (100, 3)
    assert np.array_equal(read_table(URI + "test.txt", "a"), by_hand)
    for version in ("v4", "v6", "v7"):
        stored = scipy.io.loadmat(TABLES / f"test_{version}.mat")["a"]
        assert np.array_equal(stored, by_hand), version              # the files agree
        assert np.array_equal(read_table(URI + f"test_{version}.mat", "a"), stored), version
    with h5py.File(TABLES / "test_v7.3.mat", "r") as handle:
        stored = handle["a"][()]
    assert stored.shape == (3, 100)                                  # MATLAB stores the transpose
    assert np.array_equal(stored.T, by_hand)
    assert np.array_equal(read_table(URI + "test_v7.3.mat", "a"), stored.T)


def test_akima2d_agrees_across_text_mat_and_csv(msl):
    h5py = pytest.importorskip("h5py")
    by_hand = hand_parsed(TABLES / "test.txt", "akima2D")
    assert by_hand.shape == (12, 10)
    assert np.array_equal(read_table(URI + "test.txt", "akima2D"), by_hand)
    for version in ("v4", "v6", "v7"):
        assert np.array_equal(read_table(URI + f"test_{version}.mat", "akima2D"),
                              scipy.io.loadmat(TABLES / f"test_{version}.mat")["akima2D"])
    with h5py.File(TABLES / "test_v7.3.mat", "r") as handle:
        assert np.array_equal(read_table(URI + "test_v7.3.mat", "akima2D"), handle["akima2D"][()].T)
    # ModelicaTest.Tables.CombiTable2Ds.Test32: delimiter=";", nHeaderLines=0
    csv = read_table(TEST_URI + "test2D.csv", delimiter=";", header_lines=0)
    assert np.array_equal(csv, by_hand)


def test_tab_separated_a_tab_equals_a(msl):
    assert "\t" in (TABLES / "test.txt").read_text().split("double a_tab(100,3)")[1].split("\n")[1]
    a_tab = read_table(URI + "test.txt", "a_tab")
    assert np.array_equal(a_tab, hand_parsed(TABLES / "test.txt", "a_tab"))
    assert np.array_equal(a_tab, read_table(URI + "test.txt", "a"))


def test_rows_spanning_lines_and_lines_holding_rows_with_comments(msl):
    tab1 = read_table(URI + "test.txt", "tab1")
    assert tab1.tolist() == TAB1
    # the MAT files hold the same table as the field tab1 of the struct s (and of s.s)
    stored = scipy.io.loadmat(TABLES / "test_v6.mat")["s"][0, 0]["tab1"]
    assert np.array_equal(stored, TAB1)
    assert read_table(URI + "test.txt", "tab0").tolist() == [[0, 0], [1, 1]]
    assert read_table(URI + "test.txt", "tab2").tolist() == [[0, 0], [2, 0], [2, 2], [4, 8], [6, 18], [8, 32]]


def test_struct_fields_by_dotted_name(msl):
    pytest.importorskip("h5py")
    for version in ("v6", "v7", "v7.3"):   # ModelicaTest.Tables.CombiTimeTable.Test80-82
        assert read_table(URI + f"test_{version}.mat", "s.tab1").tolist() == TAB1, version
        assert read_table(URI + f"test_{version}.mat", "s.s.tab1").tolist() == TAB1, version
    with pytest.raises(TableError, match=r'struct "s" has no field "nope"; its fields: "tab1", "s"'):
        read_table(URI + "test_v6.mat", "s.nope")
    with pytest.raises(TableError, match=r'"a" is not a struct'):
        read_table(URI + "test_v7.3.mat", "a.b")


def test_very_long_line(msl):
    long_line = read_table(URI + "test.txt", "longLine")
    assert long_line.shape == (2, 2500)
    assert np.array_equal(long_line[0], np.arange(2500))
    assert np.array_equal(long_line[1], np.arange(1, 2501))


def test_utf8_file_with_bom_and_comments(msl):
    raw = (TEST_TABLES / "test_utf8.txt").read_bytes()
    assert raw.startswith(b"\xef\xbb\xbf#1") and "☺".encode() in raw
    for name in ("a", "akima2D", "tab1"):
        assert np.array_equal(read_table(TEST_URI + "test_utf8.txt", name),
                              read_table(URI + "test.txt", name)), name


def test_csv_files_with_delimiter_and_header_lines(msl):
    # ModelicaTest.Tables.CombiTable1Ds.Test35: delimiter=",", nHeaderLines=1
    values = read_table(TEST_URI + "test1D.csv", delimiter=",", header_lines=1)
    assert np.array_equal(values, hand_parsed(TABLES / "test.txt", "a"))
    assert np.array_equal(values, read_table(TEST_URI + "test1D.csv", "Values", header_lines=1))  # name ignored
    # test.csv: "time, value" / "0.0, 0.0<TAB>" / "1,1" without a final newline
    assert read_table(TEST_URI + "test.csv", header_lines=1).tolist() == [[0, 0], [1, 1]]
    with pytest.raises(TableError) as excinfo:
        read_table(TEST_URI + "test1D.csv", delimiter=",", header_lines=0)
    text = message(excinfo)
    assert "test1D.csv" in text and "line 1" in text and '"time"' in text and "row 1" in text
    assert "header_lines" in excinfo.value.hint


def test_msl_uris_resolve_to_the_files(msl):
    assert load_resource(URI + "test.txt") == str(TABLES / "test.txt")
    assert load_resource(TEST_URI + "test.csv") == str(TEST_TABLES / "test.csv")


def test_mat_v73_without_h5py_says_how_to_install_it(msl, monkeypatch, tmp_path):
    copy = tmp_path / "copy_v7.3.mat"              # a file of its own: no cached read
    copy.write_bytes((TABLES / "test_v7.3.mat").read_bytes())
    monkeypatch.setitem(sys.modules, "h5py", None)       # import h5py fails
    with pytest.raises(TableError) as excinfo:
        read_table(str(copy), "akima2D")
    assert "pip install h5py" in message(excinfo) and "copy_v7.3.mat" in message(excinfo)


# ---------------------------------------------------------------------------
# Round trips
# ---------------------------------------------------------------------------

@pytest.mark.parametrize("fmt, compress", [("4", False), ("5", False), ("5", True)])
def test_round_trip_through_scipy_savemat(tmp_path, fmt, compress):
    rng = np.random.default_rng(7)
    matrix = rng.normal(size=(7, 4)) * 10.0 ** rng.integers(-5, 6, size=(7, 4))
    path = tmp_path / "tables.mat"
    scipy.io.savemat(path, {"tab": matrix, "other": np.eye(2)}, format=fmt, do_compression=compress)
    assert np.array_equal(read_table(str(path), "tab"), matrix)
    assert np.array_equal(read_table(str(path), "other"), np.eye(2))


def test_round_trip_integer_and_single_matrices_become_float(tmp_path):
    path = tmp_path / "ints.mat"
    scipy.io.savemat(path, {"i": np.array([[1, 2], [3, 4]], dtype=np.int16),
                            "f": np.array([[0.5, 1.5]], dtype=np.float32)})
    assert read_table(str(path), "i").dtype == np.float64
    assert read_table(str(path), "i").tolist() == [[1, 2], [3, 4]]
    assert read_table(str(path), "f").tolist() == [[0.5, 1.5]]


def test_round_trip_through_the_text_format(tmp_path):
    rng = np.random.default_rng(11)
    matrix = rng.normal(size=(5, 3)) * 1e3
    separators = [" ", "\t", ",", ";", " , ", "\t;"]
    rows = [separators[i % len(separators)].join(repr(float(v)) for v in row) for i, row in enumerate(matrix)]
    text = "#1 written by hand\n# a comment\n\ndouble m(5,3)  # trailing comment\n" + "\n".join(rows) + "\n"
    path = write(tmp_path / "m.txt", text)
    assert np.array_equal(read_table(path, "m"), matrix)


def test_text_format_details(tmp_path):
    text = ("#1\r\n"
            "float t(2,3)\r\n"           # float declares a matrix too; CRLF line ends
            "  1e0 +2.5 -.5  # one row\r\n"
            "\t3. 0x10 4E-1\r\n")        # hexadecimal as C's strtod reads it
    path = write(tmp_path / "t.dat", text)
    assert read_table(path, "t").tolist() == [[1, 2.5, -0.5], [3, 16, 0.4]]
    spanning = "#1\ndouble s(1,4)\n1\n2 # part\n# comment\n\n3 4\n"
    assert read_table(write(tmp_path / "s.txt", spanning), "s").tolist() == [[1, 2, 3, 4]]


def test_extension_is_case_insensitive(tmp_path):
    mat = tmp_path / "UPPER.MAT"
    scipy.io.savemat(mat, {"x": np.array([[1.0, 2.0]])})
    assert read_table(str(mat), "x").tolist() == [[1, 2]]
    csv = write(tmp_path / "data.Csv", "a;b\n1;2\n3;4\n")
    assert read_table(csv, delimiter=";", header_lines=1).tolist() == [[1, 2], [3, 4]]
    txt = write(tmp_path / "any.TABLE", "#1\ndouble x(1,1)\n5\n")
    assert read_table(txt, "x").tolist() == [[5]]


# ---------------------------------------------------------------------------
# Resolving modelica:// and file:// URIs
# ---------------------------------------------------------------------------

def make_file(path: Path, text: str = "#1\ndouble x(1,1)\n1\n") -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text, encoding="utf-8")
    return path


def test_modelica_path_keeps_order_and_skips_empty_entries(monkeypatch, tmp_path):
    monkeypatch.setenv("MODELICAPATH", os.pathsep.join([str(tmp_path / "b"), "", str(tmp_path / "a")]))
    assert modelica_path() == [tmp_path / "b", tmp_path / "a"]
    monkeypatch.delenv("MODELICAPATH")
    assert modelica_path() == []


def test_several_roots_are_searched_in_order(monkeypatch, tmp_path):
    one, two = tmp_path / "one", tmp_path / "two"
    a_in_one = make_file(one / "LibA" / "Resources" / "t.txt")
    b_in_two = make_file(two / "LibB" / "Resources" / "t.txt")
    shared_one = make_file(one / "Shared" / "Resources" / "t.txt")
    make_file(two / "Shared" / "Resources" / "t.txt")
    only_in_two = make_file(two / "Shared" / "Resources" / "extra.txt")
    monkeypatch.setenv("MODELICAPATH", os.pathsep.join([str(one), str(two)]))
    assert load_resource("modelica://LibA/Resources/t.txt") == str(a_in_one)
    assert load_resource("modelica://LibB/Resources/t.txt") == str(b_in_two)
    assert load_resource("modelica://Shared/Resources/t.txt") == str(shared_one)     # first root wins
    assert load_resource("modelica://Shared/Resources/extra.txt") == str(only_in_two)
    assert read_table("modelica://LibB/Resources/t.txt", "x").tolist() == [[1]]


def test_versioned_package_folder_and_nested_packages(monkeypatch, tmp_path):
    old = make_file(tmp_path / "Lib 1.9.0" / "Resources" / "t.txt")
    new = make_file(tmp_path / "Lib 1.10.0" / "Resources" / "t.txt")
    sub = make_file(tmp_path / "Lib 1.10.0" / "Sub" / "Deeper" / "data" / "t.txt")
    in_file = make_file(tmp_path / "Lib 1.10.0" / "data" / "u.txt")
    (tmp_path / "Lib 1.10.0" / "Single.mo").write_text("package Single end Single;")
    monkeypatch.setenv("MODELICAPATH", str(tmp_path))
    assert load_resource("modelica://Lib/Resources/t.txt") == str(new)               # highest version
    assert old.exists()
    assert load_resource("modelica://Lib.Sub.Deeper/data/t.txt") == str(sub)
    # a package stored in a file (Single.mo) shares the folder of that file
    assert load_resource("modelica://Lib.Single/data/u.txt") == str(in_file)
    (tmp_path / "Solo.mo").write_text("package Solo end Solo;")      # a one-file library
    beside = make_file(tmp_path / "data" / "solo.txt")
    assert load_resource("modelica://Solo/data/solo.txt") == str(beside)
    plain = make_file(tmp_path / "Lib" / "Resources" / "t.txt")
    assert load_resource("modelica://Lib/Resources/t.txt") == str(plain)             # unversioned first


def test_utf8_file_names_plain_and_percent_encoded(monkeypatch, tmp_path):
    target = make_file(tmp_path / "Lib" / "Größe" / "Résumé" / "Tabelle π.txt", "#1\ndouble π(1,2)\n1 2\n")
    monkeypatch.setenv("MODELICAPATH", str(tmp_path))
    assert load_resource("modelica://Lib/Größe/Résumé/Tabelle π.txt") == str(target)
    assert load_resource("modelica://Lib/Gr%C3%B6%C3%9Fe/R%C3%A9sum%C3%A9/Tabelle%20%CF%80.txt") == str(target)
    assert read_table("modelica://Lib/Größe/Résumé/Tabelle π.txt", "π").tolist() == [[1, 2]]
    utf8_root = make_file(tmp_path / "Wurzel ä" / "Lib2" / "t.txt")       # a root with a UTF-8 name
    monkeypatch.setenv("MODELICAPATH", str(tmp_path / "Wurzel ä"))
    assert load_resource("modelica://Lib2/t.txt") == str(utf8_root)


def test_file_uris_and_plain_paths(monkeypatch, tmp_path):
    target = make_file(tmp_path / "dir with space" / "naïve.txt")
    encoded = "file://" + str(target).replace(" ", "%20").replace("ï", "%C3%AF")
    assert load_resource(encoded) == str(target)
    assert load_resource("file://" + str(target)) == str(target)
    assert load_resource("file://localhost" + str(target)) == str(target)
    assert load_resource(str(target)) == str(target)
    monkeypatch.chdir(tmp_path)
    assert load_resource("dir with space/naïve.txt") == str(target)
    assert read_table(encoded, "x").tolist() == [[1]]


def test_unknown_package_names_the_uri_the_roots_and_the_variable(monkeypatch, tmp_path):
    monkeypatch.setenv("MODELICAPATH", os.pathsep.join([str(tmp_path / "r1"), str(tmp_path / "r2")]))
    with pytest.raises(TableError) as excinfo:
        load_resource("modelica://NoSuchLib/Resources/t.txt")
    text = message(excinfo)
    assert "modelica://NoSuchLib/Resources/t.txt" in text
    assert str(tmp_path / "r1") in text and str(tmp_path / "r2") in text
    assert "MODELICAPATH" in excinfo.value.hint
    monkeypatch.delenv("MODELICAPATH")
    with pytest.raises(TableError, match="MODELICAPATH is not set"):
        load_resource("modelica://NoSuchLib/t.txt")
    with pytest.raises(TableError, match="not a Modelica URI"):
        load_resource("modelica:NoSuchLib/t.txt")


# ---------------------------------------------------------------------------
# Errors
# ---------------------------------------------------------------------------

def test_table_error_is_a_parameter_error():
    assert issubclass(TableError, ParameterError) and issubclass(TableError, ValueError)


def test_missing_file_names_the_path_and_the_uri(monkeypatch, tmp_path):
    missing = tmp_path / "nope.txt"
    with pytest.raises(TableError) as excinfo:
        read_table(str(missing), "tab")
    assert str(missing) in message(excinfo) and '"tab"' in message(excinfo)
    assert "working directory" in excinfo.value.hint
    make_file(tmp_path / "Lib" / "package.mo")
    monkeypatch.setenv("MODELICAPATH", str(tmp_path))
    with pytest.raises(TableError) as excinfo:
        read_table("modelica://Lib/Resources/missing.mat", "tab")
    text = message(excinfo)
    assert "modelica://Lib/Resources/missing.mat" in text
    assert str(tmp_path / "Lib" / "Resources" / "missing.mat") in text


def test_table_not_in_the_text_file_lists_the_names(tmp_path):
    path = write(tmp_path / "t.txt", "#1\ndouble one(1,1)\n1\nfloat two(1,2)\n1 2\n")
    with pytest.raises(TableError) as excinfo:
        read_table(path, "three")
    text = message(excinfo)
    assert path in text and '"three"' in text and '"one", "two"' in text
    with pytest.raises(TableError, match='no table name given .* "one", "two"'):
        read_table(path)


def test_table_not_in_the_mat_file_lists_the_variables(tmp_path):
    path = tmp_path / "t.mat"
    scipy.io.savemat(path, {"alpha": np.eye(2), "beta": np.ones((1, 1))})
    with pytest.raises(TableError) as excinfo:
        read_table(str(path), "gamma")
    text = message(excinfo)
    assert str(path) in text and '"gamma"' in text and '"alpha"' in text and '"beta"' in text


def test_mat_matrix_not_2d_empty_complex_or_text(tmp_path):
    path = tmp_path / "bad.mat"
    scipy.io.savemat(path, {"cube": np.zeros((2, 2, 2)), "empty": np.zeros((0, 3)),
                            "cplx": np.array([[1 + 1j]]), "word": "text",
                            "thin": scipy.sparse.csc_matrix(np.eye(3))})
    cases = {"cube": "3 dimensions", "empty": "is empty", "cplx": "complex", "word": "not a numeric matrix",
             "thin": "not a numeric matrix (sparse)"}
    for name, expected in cases.items():
        with pytest.raises(TableError) as excinfo:
            read_table(str(path), name)
        assert expected in message(excinfo) and f'"{name}"' in message(excinfo) and str(path) in message(excinfo)


def test_mat_v73_errors(tmp_path):
    h5py = pytest.importorskip("h5py")
    path = tmp_path / "v73.mat"
    # a v7.3 file as MATLAB writes it: a 512-byte header, then HDF5 with MATLAB_class attributes
    with h5py.File(path, "w", userblock_size=512) as handle:
        handle.create_dataset("good", data=np.array([[1.0, 2.0, 3.0], [4.0, 5.0, 6.0]]).T)
        handle["good"].attrs["MATLAB_class"] = np.bytes_("double")
        handle.create_dataset("bad", data=np.array([[1.0, np.nan]]).T)
        handle["bad"].attrs["MATLAB_class"] = np.bytes_("double")
        handle.create_dataset("word", data=np.array([[104, 105]], dtype=np.uint16).T)
        handle["word"].attrs["MATLAB_class"] = np.bytes_("char")
    header = b"MATLAB 7.3 MAT-file, written by a test".ljust(116) + bytes(8) + b"\x00\x02IM"
    with open(path, "r+b") as stream:
        stream.write(header)
    assert read_table(str(path), "good").tolist() == [[1, 2, 3], [4, 5, 6]]
    with pytest.raises(TableError, match=r"row 1, column 2 is nan"):
        read_table(str(path), "bad")
    with pytest.raises(TableError, match=r"not a numeric matrix \(char\)"):
        read_table(str(path), "word")
    with pytest.raises(TableError, match=r'its variables: "bad", "good", "word"'):
        read_table(str(path), "none")


@pytest.mark.parametrize("fmt", ["4", "5"])
def test_truncated_mat_file(tmp_path, fmt):
    whole = tmp_path / "whole.mat"
    scipy.io.savemat(whole, {"a": np.arange(400.0).reshape(20, 20)}, format=fmt)
    cut = tmp_path / "cut.mat"
    cut.write_bytes(whole.read_bytes()[:1000])
    with pytest.raises(TableError) as excinfo:
        read_table(str(cut), "a")
    assert str(cut) in message(excinfo) and '"a"' in message(excinfo)
    assert "damaged or truncated" in excinfo.value.hint


def test_not_a_mat_file(tmp_path):
    path = write(tmp_path / "fake.mat", "#1\ndouble a(1,1)\n1\n" + "x" * 200)
    with pytest.raises(TableError) as excinfo:
        read_table(path, "a")
    assert "not a MATLAB MAT file" in message(excinfo) and path in message(excinfo)
    assert '"a"' in message(excinfo)


def test_first_line_must_be_the_format_version(tmp_path):
    path = write(tmp_path / "t.txt", "double a(1,1)\n1\n")
    with pytest.raises(TableError, match=r'first line must start with "#1"'):
        read_table(path, "a")
    with pytest.raises(TableError, match="an empty file"):
        read_table(write(tmp_path / "e.txt", ""), "a")


def test_declared_size_with_fewer_rows_names_the_line(tmp_path):
    path = write(tmp_path / "t.txt", "#1\ndouble a(3,2)\n1 2\n3 4\ndouble b(1,1)\n5\n")
    with pytest.raises(TableError) as excinfo:
        read_table(path, "a")
    text = message(excinfo)
    assert path in text and '"a"' in text and "line 5" in text and "(3,2)" in text
    assert "row 3, column 1" in text and "before its declared 3 rows" in text


def test_declared_size_with_more_rows_names_the_line(tmp_path):
    path = write(tmp_path / "t.txt", "#1\ndouble a(2,2)\n1 2\n3 4\n# comment\n5 6\n")
    with pytest.raises(TableError) as excinfo:
        read_table(path, "a")
    assert "line 6" in message(excinfo) and "more values than the declared size (declared as (2,2))" in message(excinfo)
    same_line = write(tmp_path / "u.txt", "#1\ndouble a(1,2)\n1 2 3\n")
    with pytest.raises(TableError, match=r"line 3 holds more values"):
        read_table(same_line, "a")


def test_file_ending_before_the_declared_size(tmp_path):
    path = write(tmp_path / "t.txt", "#1\ndouble a(3,2)\n1 2\n3 4\n")
    with pytest.raises(TableError, match=r"file ends \(line 4\) after 4 of the 6 values .*\(3,2\)"):
        read_table(path, "a")


def test_declaration_without_a_valid_size(tmp_path):
    path = write(tmp_path / "t.txt", "#1\ndouble a(x,2)\n1 2\n")
    with pytest.raises(TableError, match=r"line 2: the declaration has no valid size"):
        read_table(path, "a")
    with pytest.raises(TableError, match=r"is empty \(declared as \(0,2\), line 2\)"):
        read_table(write(tmp_path / "z.txt", "#1\ndouble a(0,2)\n"), "a")


def test_non_numeric_entry_names_line_row_and_column(tmp_path):
    path = write(tmp_path / "t.txt", "#1\ndouble a(2,3)\n1 2 3\n4 five 6\n")
    with pytest.raises(TableError) as excinfo:
        read_table(path, "a")
    text = message(excinfo)
    assert path in text and '"a"' in text and "line 4" in text and '"five"' in text and "row 2, column 2" in text
    glued = write(tmp_path / "g.txt", "#1\ndouble a(1,2)\n1 2#comment glued to a number\n")
    with pytest.raises(TableError, match=r'"2#comment" is not a number'):
        read_table(glued, "a")


@pytest.mark.parametrize("entry, shown", [("nan", "nan"), ("-inf", "-inf"), ("1e999", "inf")])
def test_non_finite_entry_names_line_row_and_column(tmp_path, entry, shown):
    path = write(tmp_path / "t.txt", f"#1\ndouble a(2,2)\n1 2\n# comment\n3 {entry}\n")
    with pytest.raises(TableError) as excinfo:
        read_table(path, "a")
    text = message(excinfo)
    assert path in text and '"a"' in text and f"row 2, column 2 (line 5) is {shown}" in text


def test_csv_errors_name_line_and_row(tmp_path):
    ragged = write(tmp_path / "r.csv", "x,y\n1,2\n3,4,5\n")
    with pytest.raises(TableError) as excinfo:
        read_table(ragged, header_lines=1)
    assert ragged in message(excinfo) and "line 3 (row 2) has 3 values" in message(excinfo)
    bad = write(tmp_path / "b.csv", "1,2\n3,abc\n")
    with pytest.raises(TableError, match=r'line 2: "abc" is not a number \(row 2, column 2\)'):
        read_table(bad)
    non_finite = write(tmp_path / "n.csv", "h\n1,2\n3,inf\n")
    with pytest.raises(TableError, match=r"row 2, column 2 \(line 3\) is inf"):
        read_table(non_finite, header_lines=1)
    with pytest.raises(TableError, match="holds no data after its 1 header lines"):
        read_table(write(tmp_path / "h.csv", "only a header\n"), header_lines=1)
    with pytest.raises(TableError, match="fewer than the 3 header lines"):
        read_table(write(tmp_path / "s.csv", "a\nb\n"), header_lines=3)
    with pytest.raises(TableError, match="single character"):
        read_table(bad, delimiter=",;")


def test_csv_blank_lines_and_separators(tmp_path):
    path = write(tmp_path / "t.csv", "\ufeff1; 2\n\n 3 ;\t4;\r\n")
    assert read_table(path, delimiter=";").tolist() == [[1, 2], [3, 4]]


# ---------------------------------------------------------------------------
# Cache, read-only results, verbose
# ---------------------------------------------------------------------------

def test_one_file_is_read_once_until_it_changes(tmp_path, monkeypatch, capsys):
    calls = []
    real = tablefiles._read_text
    monkeypatch.setattr(tablefiles, "_read_text", lambda *args: calls.append(args[1]) or real(*args))
    path = write(tmp_path / "t.txt", "#1\ndouble a(1,2)\n1 2\ndouble b(1,1)\n3\n")
    first = read_table(path, "a", verbose=True)
    assert read_table(path, "a", verbose=True) is first
    assert read_table("file://" + path, "a") is first
    assert read_table(path, "b").tolist() == [[3]]
    assert calls == ["a", "b"]
    assert capsys.readouterr().out.count(f'loading "a" from "{path}"') == 1
    time.sleep(0.01)
    write(tmp_path / "t.txt", "#1\ndouble a(1,3)\n7 8 9\n")
    assert read_table(path, "a").tolist() == [[7, 8, 9]]
    assert calls == ["a", "b", "a"]


def test_csv_reads_are_cached_per_delimiter_and_header_lines(tmp_path):
    path = write(tmp_path / "t.csv", "1,2\n3,4\n")
    whole = read_table(path)
    assert read_table(path, "ignored") is whole
    assert read_table(path, header_lines=1).tolist() == [[3, 4]]


def test_tables_are_read_only(tmp_path):
    table = read_table(write(tmp_path / "t.txt", "#1\ndouble a(1,1)\n1\n"), "a")
    with pytest.raises(ValueError):
        table[0, 0] = 2.0


# ---------------------------------------------------------------------------
# usertab
# ---------------------------------------------------------------------------

def test_usertab_registers_and_looks_up(monkeypatch):
    monkeypatch.setattr(tablefiles, "_USERTABS", {})
    register_usertab("tab1", [[0, 0], [1, 1]])
    table = usertab("tab1")
    assert table.tolist() == [[0, 0], [1, 1]] and table.dtype == np.float64
    assert not table.flags.writeable
    register_usertab("other", np.eye(2))
    with pytest.raises(TableError) as excinfo:
        usertab("missing")
    assert '"missing"' in message(excinfo) and '"other", "tab1"' in message(excinfo)
    assert "register_usertab" in excinfo.value.hint
    for bad, expected in (([1, 2], "dimensions"), ([[]], "empty"), ([[1, np.nan]], "not a finite"),
                          ([["a"]], "not a matrix of numbers")):
        with pytest.raises(TableError, match=expected):
            register_usertab("bad", bad)
