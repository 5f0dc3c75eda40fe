"""`tidyplan lsp`: the Language Server Protocol over stdio, with pygls (docs/editor.md).

Each request is answered from ``workspace.Workspace``; this module only translates between its
plain values and the protocol's types. Diagnostics are sent after every open, change and save:
the document's own, and those of the open problems of a domain that changed. A fault while
answering is logged to the client and answered as "nothing here": a broken file, or a bug of
ours, never takes the server down.
"""

from __future__ import annotations

import functools
import gc
import logging
from urllib.parse import unquote, urlparse

from lsprotocol import types as t

from tidyplan.editor.diagnose import Range
from tidyplan.editor.workspace import Workspace

try:  # pygls 2
    from pygls.lsp.server import LanguageServer
except ImportError:  # pygls 1.3
    from pygls.server import LanguageServer  # type: ignore[no-redef]

log = logging.getLogger(__name__)

_SYMBOL_KINDS = {
    "type": t.SymbolKind.Class,
    "predicate": t.SymbolKind.Boolean,
    "function": t.SymbolKind.Function,
    "action": t.SymbolKind.Method,
    "assumption": t.SymbolKind.Event,
    "object": t.SymbolKind.Constant,
    "group": t.SymbolKind.Namespace,
}
_COMPLETION_KINDS = {
    "keyword": t.CompletionItemKind.Keyword,
    "predicate": t.CompletionItemKind.Interface,
    "function": t.CompletionItemKind.Function,
    "type": t.CompletionItemKind.Class,
    "object": t.CompletionItemKind.Constant,
    "unit": t.CompletionItemKind.Module,
    "variable": t.CompletionItemKind.Variable,
}


def path_of(uri: str) -> str:
    u = urlparse(uri)
    return unquote(u.path) if u.scheme == "file" else uri


def uri_of(path: str) -> str:
    from pathlib import Path

    return Path(path).as_uri() if path.startswith("/") else path


def _range(r: Range) -> t.Range:
    return t.Range(t.Position(r.line, r.col), t.Position(r.end_line, r.end_col))


def _safe(default):
    """A handler that fails answers `default` and logs why, instead of raising into pygls."""

    def wrap(f):
        @functools.wraps(f)
        def inner(ls, params):
            try:
                return f(ls, params)
            except Exception:  # noqa: BLE001 - the editor keeps its server
                log.exception("tidyplan lsp: %s failed", f.__name__)
                return default

        return inner

    return wrap


def build() -> LanguageServer:
    from importlib.metadata import PackageNotFoundError, version

    try:
        ours = version("tidyplan")
    except PackageNotFoundError:  # run from a clone that is not installed
        ours = "0"
    server = LanguageServer("tidyplan", ours)
    ws = Workspace()
    server.tidyplan_workspace = ws  # type: ignore[attr-defined]

    def publish(ls, paths: list[str]) -> None:
        for path in paths:
            if path not in ws.docs:
                continue
            found = ws.diagnostics(path)
            diags = [
                t.Diagnostic(
                    range=_range(f.range),
                    message=f.message,
                    severity=t.DiagnosticSeverity.Warning if f.warning else t.DiagnosticSeverity.Error,
                    source=f.source,
                )
                for f in found
            ]
            params = t.PublishDiagnosticsParams(uri=uri_of(path), diagnostics=diags)
            if hasattr(ls, "text_document_publish_diagnostics"):
                ls.text_document_publish_diagnostics(params)
            else:  # pygls 1
                ls.publish_diagnostics(params.uri, params.diagnostics)

    def text_of(ls, uri: str) -> str:
        return ls.workspace.get_text_document(uri).source

    @server.feature(t.TEXT_DOCUMENT_DID_OPEN)
    @_safe(None)
    def did_open(ls, params: t.DidOpenTextDocumentParams):
        publish(ls, ws.update(path_of(params.text_document.uri), params.text_document.text))

    @server.feature(t.TEXT_DOCUMENT_DID_CHANGE)
    @_safe(None)
    def did_change(ls, params: t.DidChangeTextDocumentParams):
        uri = params.text_document.uri
        publish(ls, ws.update(path_of(uri), text_of(ls, uri)))

    @server.feature(t.TEXT_DOCUMENT_DID_SAVE)
    @_safe(None)
    def did_save(ls, params: t.DidSaveTextDocumentParams):
        uri = params.text_document.uri
        publish(ls, ws.update(path_of(uri), text_of(ls, uri)))

    @server.feature(t.TEXT_DOCUMENT_DID_CLOSE)
    @_safe(None)
    def did_close(ls, params: t.DidCloseTextDocumentParams):
        ws.close(path_of(params.text_document.uri))

    @server.feature(t.TEXT_DOCUMENT_HOVER)
    @_safe(None)
    def hover(ls, params: t.HoverParams):
        p = params.position
        found = ws.hover(path_of(params.text_document.uri), p.line, p.character)
        if found is None:
            return None
        text, r = found
        return t.Hover(contents=t.MarkupContent(kind=t.MarkupKind.Markdown, value=text), range=_range(r))

    @server.feature(t.TEXT_DOCUMENT_DEFINITION)
    @_safe(None)
    def definition(ls, params: t.DefinitionParams):
        p = params.position
        places = ws.definition(path_of(params.text_document.uri), p.line, p.character)
        return [t.Location(uri=uri_of(x.path), range=_range(x.range)) for x in places] or None

    @server.feature(t.TEXT_DOCUMENT_REFERENCES)
    @_safe(None)
    def references(ls, params: t.ReferenceParams):
        p = params.position
        places = ws.references(
            path_of(params.text_document.uri), p.line, p.character, params.context.include_declaration
        )
        return [t.Location(uri=uri_of(x.path), range=_range(x.range)) for x in places] or None

    @server.feature(t.TEXT_DOCUMENT_DOCUMENT_SYMBOL)
    @_safe([])
    def symbols(ls, params: t.DocumentSymbolParams):
        def convert(s) -> t.DocumentSymbol:
            return t.DocumentSymbol(
                name=s.name,
                kind=_SYMBOL_KINDS.get(s.kind, t.SymbolKind.Object),
                range=_range(s.range),
                selection_range=_range(s.selection),
                detail=s.detail or None,
                children=[convert(c) for c in s.children] or None,
            )

        return [convert(s) for s in ws.symbols(path_of(params.text_document.uri))]

    @server.feature(
        t.TEXT_DOCUMENT_COMPLETION, t.CompletionOptions(trigger_characters=["(", ":", "-", " ", "?"])
    )
    @_safe(None)
    def completion(ls, params: t.CompletionParams):
        p = params.position
        items = []
        for c in ws.complete(path_of(params.text_document.uri), p.line, p.character):
            snippet = bool(c.insert) and "$" in c.insert
            items.append(
                t.CompletionItem(
                    label=c.label,
                    kind=_COMPLETION_KINDS.get(c.kind, t.CompletionItemKind.Text),
                    detail=c.detail or None,
                    insert_text=c.insert or None,
                    insert_text_format=t.InsertTextFormat.Snippet if snippet else None,
                )
            )
        return t.CompletionList(is_incomplete=False, items=items)

    return server


def serve_stdio() -> int:
    server = build()
    # A keystroke's re-check makes tens of thousands of small objects (a 2,000-line domain's
    # tokens); the collector's full passes over everything the server holds then came in the
    # middle of one, 30-40 ms each (bench/lsp_latency.py's tail). What is loaded by now stays:
    # frozen out of the passes, and the young generation given room for one re-check.
    gc.freeze()
    gc.set_threshold(100_000, 20, 20)
    server.start_io()
    return 0
