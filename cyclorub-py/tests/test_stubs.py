"""The type stubs (issue 45 item 23): generated from the key table by
tools/stubs.py, so they cannot drift; shipped with py.typed."""

import importlib.util
from pathlib import Path

import cyclorub

ROOT = Path(__file__).resolve().parents[1]


def _generator():
    spec = importlib.util.spec_from_file_location("stubs", ROOT / "tools" / "stubs.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_the_committed_stubs_are_the_generated_ones():
    for name, text in _generator().stubs().items():
        committed = (ROOT / "python" / "cyclorub" / name).read_text()
        assert committed == text, (
            f"{name} differs from the key table: run `python cyclorub-py/tools/stubs.py` "
            "with the wheel installed")


def test_the_wheel_ships_the_stubs_and_py_typed():
    installed = Path(cyclorub.__file__).parent
    for name in ("py.typed", "__init__.pyi", "_case.pyi", "_result.pyi", "_errors.pyi",
                 "_study.pyi"):
        assert (installed / name).exists(), name


def test_every_key_and_table_is_typed():
    stub = (ROOT / "python" / "cyclorub" / "_case.pyi").read_text()
    for key in cyclorub.keys():
        table, name = key["key"].rsplit(".", 1)
        assert f"\n    {name}: " in stub, key["key"]
    assert "    contact: _Contact\n" in stub
    assert "    damping: _ModelDamping\n" in stub
    assert 'law: Literal["regularized", "dlft"]' in stub
    result = (ROOT / "python" / "cyclorub" / "_result.pyi").read_text()
    for name in cyclorub.Result._ARRAYS:
        assert f"\n    {name}: " in result, name
