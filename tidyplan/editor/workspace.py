"""The editor's view of the files: each open document with its index and diagnostics, a problem
tied to its domain, and the answers to the editor's questions (hover, definition, references,
outline, completion), in plain values. ``server.py`` turns them into the protocol's types;
nothing here imports pygls, so the benchmark and tests can use it alone.

A problem is checked against the domain its ``(:domain NAME)`` names: an open document first,
else a ``.pddl`` file beside it on disk, in its parent folder or in a folder beside its own
(``problems/`` next to ``domains/``). Every answer is computed from the last text the editor
sent; a text that does not parse keeps the model of its last good text for hover.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from pathlib import Path

from tidyplan.editor import index as ix_mod
from tidyplan.editor.answers import Completion, Place, Symbol, _node_range, _offset, _range  # noqa: F401
from tidyplan.editor.diagnose import Checked, Found, Range, check
from tidyplan.editor.index import Index, Occurrence
from tidyplan.editor.sexpr import Node, enclosing, header
from tidyplan.pddl import model as m


@dataclass(slots=True)
class Document:
    path: str
    text: str
    index: Index
    checked: Checked | None = None
    last_model: m.Domain | m.Problem | None = None


@dataclass
class Workspace:
    docs: dict[str, Document] = field(default_factory=dict)
    _disk: dict[str, tuple[float, tuple[str, str] | None]] = field(default_factory=dict)

    # ------------------------------------------------------------ documents
    def update(self, path: str, text: str) -> list[str]:
        """Take a document's new text; the paths whose diagnostics changed with it (itself, and
        the open problems of a domain)."""
        doc = self.docs.get(path)
        ix = ix_mod.build(text)
        if doc is None:
            doc = self.docs[path] = Document(path, text, ix)
        else:
            doc.text, doc.index = text, ix
        doc.checked = None
        touched = [path]
        if ix.kind == "domain":
            for other in self.docs.values():
                if other.path != path and other.index.kind == "problem":
                    other.checked = None
                    touched.append(other.path)
        return touched

    def close(self, path: str) -> None:
        self.docs.pop(path, None)

    def diagnostics(self, path: str) -> list[Found]:
        doc = self.docs[path]
        if doc.checked is None:
            domain = None
            notes: list[Found] = []
            if doc.index.kind == "problem":
                domain, notes = self._domain_model(doc)
            doc.checked = check(doc.text, path, doc.index, domain)
            doc.checked.found[:0] = notes
            if doc.checked.model is not None and doc.checked.complete:
                doc.last_model = doc.checked.model
        return doc.checked.found

    # ------------------------------------------------------- problem → domain
    def domain_of(self, doc: Document) -> Document | None:
        name = doc.index.domain_name
        if not name:
            return None
        for other in self.docs.values():
            if other.index.kind == "domain" and other.index.name == name:
                return other
        for candidate in self._beside(doc.path):
            if self._header(candidate) == ("domain", name):
                try:
                    text = Path(candidate).read_text(encoding="utf-8-sig")
                except (OSError, UnicodeDecodeError):
                    continue
                return Document(candidate, text, ix_mod.build(text))
        return None

    def _domain_model(self, doc: Document) -> tuple[m.Domain | None, list[Found]]:
        d = self.domain_of(doc)
        name = doc.index.domain_name
        where = next((o.token for o in doc.index.occurrences if o.kind == "domain"), None)
        at = _range(where) if where else Range(0, 0, 0, 1)
        if d is None:
            if not name:
                return None, []
            return None, [
                Found(at, f"domain '{name}' not found among the open files nor beside this one", True)
            ]
        if d.path not in self.docs or self.docs[d.path] is not d:  # from disk: check it once
            d.checked = check(d.text, d.path, d.index)
            d.last_model = d.checked.model if d.checked.complete else None
        elif d.checked is None:
            self.diagnostics(d.path)
        model = d.last_model
        if not isinstance(model, m.Domain):
            return None, [
                Found(
                    at,
                    f"domain '{name}' ({d.path}) does not read; the problem is checked for syntax only",
                    True,
                )
            ]
        return model, []

    def _beside(self, path: str) -> list[str]:
        here = Path(path).resolve().parent
        folders = [here, here.parent]
        try:
            folders += sorted(p for p in here.parent.iterdir() if p.is_dir() and p != here)
        except OSError:
            pass
        out: list[str] = []
        for folder in folders:
            try:
                out += sorted(str(p) for p in folder.glob("*.pddl") if str(p) != str(Path(path).resolve()))
            except OSError:
                continue
        return out

    def _header(self, path: str) -> tuple[str, str] | None:
        try:
            mtime = os.stat(path).st_mtime
        except OSError:
            return None
        cached = self._disk.get(path)
        if cached is not None and cached[0] == mtime:
            return cached[1]
        try:
            with open(path, encoding="utf-8-sig", errors="replace") as f:
                head = header(f.read(16384))
        except OSError:
            head = None
        self._disk[path] = (mtime, head)
        return head

    # ------------------------------------------------------------ questions
    def _related(self, doc: Document) -> list[Document]:
        """The documents whose names this one shares: a problem's domain; a domain's problems."""
        out = [doc]
        if doc.index.kind == "problem":
            d = self.domain_of(doc)
            if d is not None:
                out.append(d)
                doc = d
        if doc.index.kind == "domain":
            out += [
                o
                for o in self.docs.values()
                if o.index.kind == "problem" and o.index.domain_name == doc.index.name and o not in out
            ]
        return out

    def occurrence(self, path: str, line: int, col: int) -> tuple[Document, Occurrence | None]:
        doc = self.docs[path]
        return doc, doc.index.at(_offset(doc.text, line, col))

    def definition(self, path: str, line: int, col: int) -> list[Place]:
        doc, o = self.occurrence(path, line, col)
        if o is None:
            return []
        scope = o.scope if o.kind == "variable" else ""
        for d in self._related(doc) if o.kind != "variable" else [doc]:
            found = d.index.definitions(o.kind, o.name, scope)
            if found:
                return [Place(d.path, _range(x.token)) for x in found]
        return []

    def references(self, path: str, line: int, col: int, include_declaration: bool = True) -> list[Place]:
        doc, o = self.occurrence(path, line, col)
        if o is None:
            return []
        scope = o.scope if o.kind == "variable" else ""
        out = []
        for d in self._related(doc) if o.kind != "variable" else [doc]:
            for x in d.index.uses(o.kind, o.name, scope):
                if include_declaration or not x.definition:
                    out.append(Place(d.path, _range(x.token)))
        return out

    def hover(self, path: str, line: int, col: int) -> tuple[str, Range] | None:
        from tidyplan.editor.hover import describe

        doc, o = self.occurrence(path, line, col)
        if o is None:
            return None
        text = describe(self, doc, o)
        return (text, _range(o.token)) if text else None

    def symbols(self, path: str) -> list[Symbol]:
        from tidyplan.editor.outline import outline

        return outline(self.docs[path])

    def complete(self, path: str, line: int, col: int) -> list[Completion]:
        from tidyplan.editor.complete import complete

        doc = self.docs[path]
        return complete(self, doc, _offset(doc.text, line, col))

    def enclosing(self, doc: Document, offset: int) -> list[Node]:
        return enclosing(doc.index.top, offset)
