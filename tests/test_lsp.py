"""`tidyplan lsp` driven as an editor drives it: a real client over stdio (pytest-lsp), on
domains/tidy.pddl and problems/tidy-p1.pddl (docs/editor.md)."""

from __future__ import annotations

import re
import sys
from pathlib import Path

import pytest

pytest_lsp = pytest.importorskip("pytest_lsp", reason="the lsp extra (pygls, pytest-lsp) is not installed")
from lsprotocol import types as t  # noqa: E402
from pytest_lsp import ClientServerConfig, LanguageClient  # noqa: E402

REPO = Path(__file__).resolve().parent.parent
DOMAIN = REPO / "domains" / "tidy.pddl"
PROBLEM = REPO / "problems" / "tidy-p1.pddl"


@pytest_lsp.fixture(config=ClientServerConfig(server_command=[sys.executable, "-m", "tidyplan", "lsp"]))
async def client(lsp_client: LanguageClient):
    await lsp_client.initialize_session(t.InitializeParams(capabilities=t.ClientCapabilities()))
    yield
    await lsp_client.shutdown_session()


# ------------------------------------------------------------------ helpers
def where(text: str, needle: str, start: int = 0) -> t.Range:
    """The range of the first `needle` at or after offset `start`."""
    at = text.index(needle, start)
    line = text.count("\n", 0, at)
    col = at - (text.rfind("\n", 0, at) + 1)
    return t.Range(t.Position(line, col), t.Position(line, col + len(needle)))


def inside(text: str, needle: str, after: str = "") -> t.Position:
    """A place inside the first `needle` after `after`."""
    r = where(text, needle, text.index(after) if after else 0)
    return t.Position(r.start.line, r.start.character + 1)


async def opened(client, path: Path, text: str | None = None, version: int = 1) -> str:
    uri = path.as_uri()
    text = path.read_text() if text is None else text
    client.text_document_did_open(t.DidOpenTextDocumentParams(t.TextDocumentItem(uri, "pddl", version, text)))
    await settled(client, uri)
    return uri


async def settled(client, uri: str) -> None:
    """Wait until the server has handled everything sent before: it answers requests in order,
    and publishes a change's diagnostics before it reads the next message, so once a request
    sent now is answered, every diagnostic of the change has arrived."""
    await client.text_document_document_symbol_async(t.DocumentSymbolParams(doc(uri)))
    assert uri in client.diagnostics


async def changed(client, uri: str, version: int, changes) -> list[t.Diagnostic]:
    client.text_document_did_change(
        t.DidChangeTextDocumentParams(t.VersionedTextDocumentIdentifier(version=version, uri=uri), changes)
    )
    await settled(client, uri)
    return list(client.diagnostics[uri])


def key(r: t.Range) -> tuple[int, int, int, int]:
    return (r.start.line, r.start.character, r.end.line, r.end.character)


def doc(uri: str) -> t.TextDocumentIdentifier:
    return t.TextDocumentIdentifier(uri)


# ---------------------------------------------------------------- mistakes
# (what is written instead, the token the diagnostic must cover, part of its message, warning?)
MISTAKES = [
    (
        ("(hand-empty))\n    :effect (and (holding ?o)", "(hand-emty))\n    :effect (and (holding ?o)"),
        [("hand-emty", "undeclared predicate 'hand-emty'", False)],
    ),
    (
        (
            "(accepts ?d ?c)\n                       (not (closed",
            "(accepts ?d)\n                       (not (closed",
        ),
        [("accepts", "'accepts' takes 2 arguments, given 1", False)],
    ),
    (
        (
            ":probability 0.98\n    :units ((approach_deposit",
            ":probability 1.5\n    :units ((approach_deposit",
        ),
        [("1.5", "probability 1.5 of 'deliver_it' is outside (0, 1]", False)],
    ),
    (
        (":stratum 2\n    :units ((adjust_pose ?to))\n", ":stratum 0\n"),
        [
            ("0", "stratum of 'possible_ego_pose_adjustment' must be a whole number of at least 1", False),
        ],
    ),
    (
        ("(item-at ?o ?w)))\n", "(item-at ?o ?w) (increase (total-cost) 2)))\n"),
        [("increase", "assumption 'assume-item-near' has a cost effect", False)],
    ),
    (
        ("(not (pull-blocked ?d)))\n    :effect", "(not (pull-blocked ?x)))\n    :effect"),
        [("pull-blocked", "undeclared variable '?x'", False)],
    ),
    (
        ("((put_down ?o))", "((put_away ?o))"),
        [("put_away", "unknown unit 'put_away' in 'drop_object'", False)],
    ),
    (
        ("(pull_handle ?d)", "(pull_handle ?w)"),
        [("pull_handle", "unit 'pull_handle' takes a deposit as deposit; '?w' is a waypoint", False)],
    ),
    (
        (
            "(shortest-paths))                            ;",
            "(shortest-paths)\n    (tidied ?o - item))                            ;",
        ),
        [("tidied", "predicate 'tidied' is declared twice", False)],
    ),
    (
        (
            ":parameters (?o - item ?w - waypoint)\n    :stratum 3",
            ":parameters (?o - item ?w - waypint)\n    :stratum 3",
        ),
        [("?w", "undeclared type 'waypint' of parameter '?w'", False)],
    ),
    (
        (":strata :assumptions", ":assumptions"),
        [("possible_ego_pose_adjustment", "uses an extension without the requirement :strata", True)],
    ),
    (
        (
            ":stratum 3\n    :units ((navigate ?to))",
            ":stratum 3\n    :units ((navigate ?from ?to))",
        ),
        [("navigate", "unit (navigate to:waypoint) takes 1 argument, given 2", False)],
    ),
    (
        (":stratum 1\n    :units ((navigate ?to))", ":stratum one\n    :units ((navigate ?to))"),
        [("one", "unexpected 'one'", False)],
    ),
]


def _apply(text: str, mistakes) -> tuple[str, list[tuple[t.Range, str, bool]]]:
    """The text with the mistakes made, and each expected diagnostic's range."""
    marks = []
    for (old, new), _ in mistakes:
        assert text.count(old) == 1, old
        marks.append(text.index(old))
        text = text.replace(old, new)
    expected = []
    for ((_, new), wants), _at in zip(mistakes, marks, strict=True):
        at = text.index(new)
        for token, message, warning in wants:
            expected.append((where(text, token, at), message, warning))
    return text, expected


def _matches(diags, expected) -> list:
    missing = []
    for r, message, warning in expected:
        hits = [d for d in diags if message in d.message and d.range == r]
        severity = t.DiagnosticSeverity.Warning if warning else t.DiagnosticSeverity.Error
        if not hits or hits[0].severity != severity:
            missing.append((r, message, [(d.range, d.message) for d in diags if message in d.message]))
    return missing


@pytest.mark.asyncio
@pytest.mark.parametrize("mistake", MISTAKES, ids=lambda m: m[1][0][1][:40])
async def test_each_mistake_is_reported_on_its_token(client, mistake):
    text, expected = _apply(DOMAIN.read_text(), [mistake])
    uri = await opened(client, DOMAIN, text)
    assert _matches(client.diagnostics[uri], expected) == []


@pytest.mark.asyncio
async def test_every_mistake_at_once_is_reported_at_once(client):
    """Thirteen kinds of mistake in one file, a syntax error among them: each on its range."""
    text, expected = _apply(DOMAIN.read_text(), MISTAKES)
    uri = await opened(client, DOMAIN, text)
    assert len(expected) == len(MISTAKES) >= 10
    assert _matches(client.diagnostics[uri], expected) == []


@pytest.mark.asyncio
async def test_two_syntax_errors_in_two_actions_are_both_reported(client):
    text = DOMAIN.read_text()
    text = text.replace(":stratum 2\n", ":stratum two\n").replace(
        ":probability 0.98\n    :units ((put", ":probability x\n    :units ((put"
    )
    uri = await opened(client, DOMAIN, text)
    found = {(d.range.start.line, d.message.split(";")[0]) for d in client.diagnostics[uri]}
    assert (where(text, ":stratum two").start.line, "unexpected 'two'") in found
    assert (where(text, ":probability x").start.line, "unexpected 'x'") in found


@pytest.mark.asyncio
async def test_an_unbalanced_parenthesis_is_reported_where_the_reader_lost_it(client):
    """One message, on the action whose '(' the reader found never closed (later ones would
    only guess: the structure after a lost parenthesis is unknown)."""
    text = DOMAIN.read_text().replace("(:action deliver_it\n", "(:action deliver_it (\n", 1)
    uri = await opened(client, DOMAIN, text)
    [d] = client.diagnostics[uri]
    assert d.message.startswith("unbalanced parenthesis: '(' is never closed")
    assert d.range == where(text, "(", text.index("(:action deliver_it"))


@pytest.mark.asyncio
async def test_a_clean_domain_and_problem_have_no_diagnostics(client):
    uri = await opened(client, DOMAIN)
    assert list(client.diagnostics[uri]) == []
    puri = await opened(client, PROBLEM)
    assert list(client.diagnostics[puri]) == []


@pytest.mark.asyncio
async def test_a_sequence_of_edits_breaks_and_mends_the_file(client):
    text = DOMAIN.read_text()
    uri = await opened(client, DOMAIN, text)
    assert list(client.diagnostics[uri]) == []
    # 1. a typo, typed as an incremental change: one character deleted
    r = where(text, "hand-empty))\n    :effect (and (holding")
    typo = t.Range(
        t.Position(r.start.line, r.start.character + 7), t.Position(r.start.line, r.start.character + 8)
    )
    diags = await changed(client, uri, 2, [t.TextDocumentContentChangePartial(range=typo, text="")])
    assert [(d.range, d.message) for d in diags] == [
        (
            t.Range(r.start, t.Position(r.start.line, r.start.character + 9)),
            "undeclared predicate 'hand-emty'",
        )
    ]
    # 2. a second mistake elsewhere: both reported
    s = where(text, ":stratum 2")
    zero = t.Range(t.Position(s.start.line, s.start.character + 9), s.end)
    diags = await changed(client, uri, 3, [t.TextDocumentContentChangePartial(range=zero, text="0")])
    assert sorted(d.message for d in diags) == [
        "stratum of 'possible_ego_pose_adjustment' must be a whole number of at least 1",
        "undeclared predicate 'hand-emty'",
    ]
    # 3. the whole define left open: a syntax error, the server still answers
    last = text.rstrip().count("\n")
    end = t.Range(
        t.Position(last, len(text.rstrip().splitlines()[-1]) - 1),
        t.Position(last, len(text.rstrip().splitlines()[-1])),
    )
    diags = await changed(client, uri, 4, [t.TextDocumentContentChangePartial(range=end, text="")])
    assert any("never closed" in d.message for d in diags), diags
    symbols = await client.text_document_document_symbol_async(t.DocumentSymbolParams(doc(uri)))
    assert "stratum P1" in [s.name for s in symbols]  # the outline of a broken file
    # 4. mended, all three: nothing left
    diags = await changed(client, uri, 5, [t.TextDocumentContentChangeWholeDocument(text=text)])
    assert diags == []


# ------------------------------------------------------------------ hover
async def _hover(client, uri, pos) -> str:
    h = await client.text_document_hover_async(t.HoverParams(doc(uri), pos))
    assert h is not None
    return h.contents.value


@pytest.mark.asyncio
async def test_hover_an_action_shows_parameters_probability_stratum_units_and_cost(client):
    text = DOMAIN.read_text()
    uri = await opened(client, DOMAIN)
    h = await _hover(client, uri, inside(text, "take_object", "(:action take_object"))
    assert "(take_object ?o - item ?w - waypoint)" in h
    assert "stratum **P1**" in h and "probability **0.95**" in h and "cost **5.7**" in h
    assert "(adjust_base ?o) (grasp ?o)" in h
    h = await _hover(client, uri, inside(text, "move", "(:action move\n"))
    assert "cost **(travel-time ?from ?to)**" in h and "probability **1**" in h
    h = await _hover(client, uri, inside(text, "possible_ego_pose_adjustment", "(:action possible"))
    assert "stratum **P2**" in h


@pytest.mark.asyncio
async def test_hover_an_assumption_shows_its_probability(client):
    text = DOMAIN.read_text()
    uri = await opened(client, DOMAIN)
    h = await _hover(client, uri, inside(text, "assume-item-near", "(:assumption"))
    assert h.startswith("assumption `assume-item-near`")
    assert "probability **(p-item-near ?w)**" in h and "cost **0 (an assumption)**" in h


@pytest.mark.asyncio
async def test_hover_a_unit_shows_its_description_and_the_worlds_that_offer_it(client):
    from tidyplan.exec.binding_check import offered

    text = DOMAIN.read_text()
    uri = await opened(client, DOMAIN)
    h = await _hover(client, uri, inside(text, "grasp", ":units ((adjust_base ?o) "))
    spec, worlds = next((s, w) for s, w in offered() if s.name == "grasp")
    assert spec.signature in h and spec.summary in h
    assert worlds and f"offered by: {', '.join(worlds)}" in h


@pytest.mark.asyncio
async def test_hover_a_predicate_or_type_shows_its_declaration(client):
    text = DOMAIN.read_text()
    uri = await opened(client, DOMAIN)
    h = await _hover(client, uri, inside(text, "item-at", "(:action take_object"))
    assert "(item-at ?o - item ?w - waypoint)" in h
    h = await _hover(client, uri, inside(text, "deposit", "(:action open_drawer"))
    assert h.startswith("type `deposit`") and "deposit - object" in h


# ------------------------------------------------------- definition, references
@pytest.mark.asyncio
@pytest.mark.parametrize(
    "name, after, declared_after",
    [
        ("item-at", "(:action take_object", "(:predicates"),  # a predicate
        ("waypoint", "(:action move\n", "(:types"),  # a type
        ("travel-time", "(increase (total-cost) (travel-time", "(:functions"),  # a function
        ("?to", ":units ((navigate ?to))", "(:action move\n"),  # a parameter
    ],
)
async def test_definition_of_a_name_is_its_declaration(client, name, after, declared_after):
    text = DOMAIN.read_text()
    uri = await opened(client, DOMAIN)
    found = await client.text_document_definition_async(
        t.DefinitionParams(doc(uri), inside(text, name, after))
    )
    assert [(x.uri, x.range) for x in found] == [(uri, where(text, name, text.index(declared_after)))]


def _uses(text: str, pattern: str) -> int:
    """Counted the plain way, outside comments."""
    code = "\n".join(line.split(";")[0] for line in text.splitlines())
    return len(re.findall(pattern, code))


@pytest.mark.asyncio
async def test_references_find_every_use(client):
    text = DOMAIN.read_text()
    uri = await opened(client, DOMAIN)
    for name, pattern in [
        ("holding", r"\(holding\b"),
        ("deposit", r"- deposit\b"),
        ("move", r"\(:action move\b"),
    ]:
        pos = inside(text, name, "(:action deliver_it" if name != "move" else "(:action move\n")
        refs = await client.text_document_references_async(
            t.ReferenceParams(
                text_document=doc(uri), position=pos, context=t.ReferenceContext(include_declaration=True)
            )
        )
        extra = 1 if name == "deposit" else 0  # its declaration in (:types ...)
        assert len(refs) == _uses(text, pattern) + extra, name


@pytest.mark.asyncio
async def test_a_problem_goes_to_its_domain_and_its_objects(client):
    """The problem's names: its types and predicates are the domain's (found beside it on disk,
    in ../domains), its objects its own."""
    ptext, dtext = PROBLEM.read_text(), DOMAIN.read_text()
    puri = await opened(client, PROBLEM)
    found = await client.text_document_definition_async(
        t.DefinitionParams(doc(puri), inside(ptext, "item-at", "(:init"))
    )
    assert [(x.uri, x.range) for x in found] == [
        (DOMAIN.as_uri(), where(dtext, "item-at", dtext.index("(:predicates")))
    ]
    found = await client.text_document_definition_async(
        t.DefinitionParams(doc(puri), inside(ptext, "wp-o1", "(:init"))
    )
    assert [(x.uri, x.range) for x in found] == [(puri, where(ptext, "wp-o1", ptext.index("(:objects")))]
    refs = await client.text_document_references_async(
        t.ReferenceParams(
            text_document=doc(puri),
            position=inside(ptext, "o4 - item"),
            context=t.ReferenceContext(include_declaration=True),
        )
    )
    assert len(refs) == _uses(ptext, r"(?<![\w-])o4(?![\w-])")
    h = await _hover(client, puri, inside(ptext, "item", "o1 o2 o3 o4 - "))
    assert "(in " in h and "tidy.pddl" in h


@pytest.mark.asyncio
async def test_a_problem_is_checked_against_its_domain(client):
    text = PROBLEM.read_text()
    bad = text.replace("(robot-at wp-entrance) (hand-empty)", "(robot-at wp-entrnce) (hand-empty wp-o1)")
    bad = bad.replace("o1 o2 o3 o4 - item", "o1 o2 o3 o4 - itm")
    puri = await opened(client, PROBLEM, bad)
    got = {(key(d.range), d.message) for d in client.diagnostics[puri]}
    assert (key(where(bad, "robot-at", bad.index("(:init"))), "undeclared object 'wp-entrnce'") in got
    assert (
        key(where(bad, "hand-empty", bad.index("(:init"))),
        "'hand-empty' takes 0 arguments, given 1",
    ) in got
    o1 = where(bad, "o1 o2 o3 o4 - itm").start
    assert ((o1.line, o1.character, o1.line, o1.character + 2), "undeclared type 'itm' of object 'o1'") in got


@pytest.mark.asyncio
async def test_a_problem_follows_its_domain_open_in_the_editor(client):
    """The domain open (and edited, unsaved) is the one the problem is checked against; its
    problems' diagnostics follow each change of it."""
    dtext, ptext = DOMAIN.read_text(), PROBLEM.read_text()
    puri = await opened(client, PROBLEM)
    assert list(client.diagnostics[puri]) == []
    duri = await opened(client, DOMAIN)
    renamed = dtext.replace("(hand-empty)\n", "(hand-free)\n", 1)
    await changed(client, duri, 2, [t.TextDocumentContentChangeWholeDocument(renamed)])
    assert (key(where(ptext, "hand-empty", ptext.index("(:init"))), "undeclared predicate 'hand-empty'") in {
        (key(d.range), d.message) for d in client.diagnostics[puri]
    }


@pytest.mark.asyncio
async def test_a_problem_whose_domain_is_nowhere_says_so(client, tmp_path):
    p = tmp_path / "p.pddl"
    p.write_text(PROBLEM.read_text().replace("(:domain tidy)", "(:domain nowhere)"))
    uri = await opened(client, p)
    [d] = client.diagnostics[uri]
    assert "domain 'nowhere' not found" in d.message and d.severity == t.DiagnosticSeverity.Warning
    assert d.range == where(p.read_text(), "nowhere")


# --------------------------------------------------------- outline, completion
@pytest.mark.asyncio
async def test_the_outline_has_types_predicates_actions_by_stratum_and_assumptions(client):
    uri = await opened(client, DOMAIN)
    symbols = await client.text_document_document_symbol_async(t.DocumentSymbolParams(doc(uri)))
    tree = {s.name: [c.name for c in s.children or []] for s in symbols}
    assert tree["types"] == ["waypoint", "item", "deposit", "category"]
    assert "robot-at" in tree["predicates"] and len(tree["predicates"]) == 20
    assert tree["stratum P1"] == ["move", "take_object", "deliver_it", "open_drawer"]
    assert tree["stratum P2"] == ["possible_ego_pose_adjustment"]
    assert tree["stratum P3"] == ["drop_object", "move_back"]
    assert tree["assumptions"] == ["assume-item-near"]


async def _labels(client, uri, pos) -> dict[str, t.CompletionItem]:
    found = await client.text_document_completion_async(t.CompletionParams(doc(uri), pos))
    return {c.label: c for c in found.items}


@pytest.mark.asyncio
async def test_completion_inside_units_offers_the_units_with_their_arguments(client):
    from tidyplan.exec.catalogue import UNITS

    text = DOMAIN.read_text().replace(":units ((put_down ?o))", ":units ((put_down ?o) ())")
    uri = await opened(client, DOMAIN, text)
    r = where(text, "())")
    items = await _labels(client, uri, t.Position(r.start.line, r.start.character + 1))
    assert set(items) == set(UNITS)
    assert items["place"].insert_text == "place ${1:item} ${2:deposit} ${3:at}"
    assert items["place"].detail.startswith("(place item:item deposit:deposit at:waypoint)")


@pytest.mark.asyncio
async def test_completion_offers_keywords_predicates_and_types(client):
    text = DOMAIN.read_text()
    uri = await opened(client, DOMAIN)
    items = await _labels(client, uri, inside(text, "robot-at", ":precondition (and (robot-at ?w)"))
    assert {":precondition", ":stratum", ":units", ":probability", "item-at", "holding"} <= set(items)
    assert items["item-at"].kind == t.CompletionItemKind.Interface
    assert items["item-at"].detail == "(item-at ?o - item ?w - waypoint)"
    typed = text.replace("(?o - item ?w - waypoint)\n    :stratum 3", "(?o - item ?w - )\n    :stratum 3")
    uri = await opened(client, DOMAIN, typed, version=2)
    r = where(typed, "?w - )")
    items = await _labels(client, uri, t.Position(r.start.line, r.start.character + 5))
    assert set(items) == {"waypoint", "item", "deposit", "category", "object"}


@pytest.mark.asyncio
async def test_completion_in_a_problem_offers_its_domains_predicates(client):
    text = PROBLEM.read_text()
    uri = await opened(client, PROBLEM)
    items = await _labels(client, uri, inside(text, "robot-at", "(:init"))
    assert {"robot-at", "item-at", "shortest-paths", ":goal", "o1", "wp-tray"} <= set(items)
    assert ":precondition" not in items
