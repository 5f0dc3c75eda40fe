"""`tidyplan lsp` and `tidyplan serve`: the dialect in an editor (docs/editor.md)."""

from __future__ import annotations

from tidyplan.errors import InputError

LSP_MISSING = "tidyplan lsp needs pygls and lsprotocol: pip install 'tidyplan[lsp]'"


def add_parsers(sub, positive) -> None:
    sub.add_parser("lsp", help="a language server for the dialect over stdio (for an editor)")
    s = sub.add_parser("serve", help="an HTTP planner service with the VS Code PDDL extension's /solve")
    s.add_argument("--host", default="127.0.0.1", help="address to listen on (default: loopback only)")
    s.add_argument("--port", type=int, default=5555, help="port (default 5555; 0 picks a free one)")
    s.add_argument(
        "--time-limit",
        type=positive,
        default=None,
        metavar="S",
        help="the longest a request may plan, whatever it asks (default 60)",
    )


def cmd_lsp(args) -> int:
    try:
        from tidyplan.editor.server import serve_stdio
    except ImportError:
        raise InputError(LSP_MISSING) from None
    return serve_stdio()


def cmd_serve(args) -> int:
    from tidyplan.editor.service import DEFAULT_LIMIT, serve

    return serve(args.host, args.port, args.time_limit or DEFAULT_LIMIT)
