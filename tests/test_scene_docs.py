"""docs/scene.md is generated from the keys the validation checks (flexbearing.studies.input_docs):
it must equal a fresh generation, and a key added to a table without its line must fail."""
from __future__ import annotations

from pathlib import Path

import pytest

from flexbearing.simulation import scene as S
from flexbearing.simulation.scene_keys import SPEC
from flexbearing.studies import input_docs

DOC = Path(__file__).resolve().parents[1] / "docs" / "scene.md"


def test_scene_md_is_current():
    assert DOC.read_text(encoding="utf-8") == input_docs.markdown(), (
        "docs/scene.md is out of date: python -m flexbearing.studies.input_docs > docs/scene.md")


def test_a_key_without_its_line_fails(monkeypatch):
    monkeypatch.setitem(S.SCENE_TABLES, "bearing", S.SCENE_TABLES["bearing"] + ("new_key",))
    monkeypatch.setattr(input_docs, "SCENE_TABLES", S.SCENE_TABLES)
    with pytest.raises(KeyError, match=r"\[bearing\]: keys \['new_key'\] have no line"):
        input_docs.markdown()


def test_no_stale_lines():
    """Every line of the key table is a key the validation accepts."""
    for table, spec in SPEC.items():
        assert set(spec) <= set(S.SCENE_TABLES[table]), table


def test_validation_uses_the_tables():
    """An unknown key is refused with the table's list of allowed keys (the same tuple the page lists)."""
    from flexbearing.common.validation import InputError
    with pytest.raises(InputError, match="guide_land_diameter"):
        S.parse_scene({"bearing": {"no_such_key": 1.0}})
