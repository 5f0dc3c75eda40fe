"""The editor reads a domain section by section (tidyplan.editor.sections): the model it makes is
the one the whole file makes, derived predicates' rules included."""

from __future__ import annotations

from pathlib import Path

from tidyplan.editor.diagnose import check
from tidyplan.editor.index import build
from tidyplan.pddl.reader import parse

DERIVED = Path(__file__).parent / "data" / "derived" / "domain.pddl"


def test_a_domain_read_by_sections_keeps_its_derived_rules():
    text = DERIVED.read_text()
    whole = parse(text, str(DERIVED))
    assert whole.derived  # the fixture has rules
    checked = check(text, str(DERIVED), build(text))
    assert checked.model == whole and checked.model.derived == whole.derived
