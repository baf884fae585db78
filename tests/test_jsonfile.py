"""The shared JSON-object reader names the file and what is wrong with it."""

from __future__ import annotations

import pytest

from rlff.errors import InputError
from rlff.jsonfile import read_json_object


def test_reads_an_object(tmp_path):
    path = tmp_path / "a.json"
    path.write_text('{"format": "x", "values": [1, 2]}', encoding="utf-8")
    assert read_json_object(path) == {"format": "x", "values": [1, 2]}


@pytest.mark.parametrize(
    ("content", "message"),
    [
        (None, "a.json: no such file"),
        (b"\xff\xfe\x00binary", "a.json: not a text file"),
        (b'{"a": 1,\n "b": }', "a.json: not valid JSON (line 2, column"),
        (b"[1, 2]", "a.json: expected a JSON object, got list"),
    ],
)
def test_bad_files_are_named(tmp_path, content, message):
    path = tmp_path / "a.json"
    if content is not None:
        path.write_bytes(content)
    with pytest.raises(InputError) as info:
        read_json_object(path)
    assert message in str(info.value)
