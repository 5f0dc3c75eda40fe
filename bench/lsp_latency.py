"""How long `tidyplan lsp` takes to answer a change of a 2,000-line domain with its diagnostics.

A domain of about 2,000 lines is made from domains/tidy.pddl (its actions repeated under new
names); a real client (pygls's, over stdio, as an editor) opens it, then types: each change is
one character in one action (a typo and its repair, alternately), sent as an incremental change,
and the time is from sending the change to receiving its diagnostics. Printed: the median and
the worst of N changes, and, in this process, the parts of one re-check (index, read, checks) as
the server does them, after the first (a cold one: every section read) and after a keystroke.

    python bench/lsp_latency.py [--changes N]
"""

from __future__ import annotations

import argparse
import asyncio
import statistics
import sys
import time
from pathlib import Path

from lsprotocol import types as t
from pygls.lsp.client import LanguageClient

REPO = Path(__file__).resolve().parent.parent


def big_domain(lines: int = 2000) -> str:
    text = (REPO / "domains" / "tidy.pddl").read_text()
    body = text[text.index("(:assumption") : text.rstrip().rindex(")")]
    out, i = text.rstrip()[:-1], 0
    while out.count("\n") < lines:
        out += "\n" + body.replace("(:action ", f"(:action c{i}-").replace(
            "(:assumption ", f"(:assumption c{i}-"
        )
        i += 1
    return out + ")\n"


async def through_the_server(text: str, changes: int) -> list[float]:
    client = LanguageClient("bench", "1")
    got: asyncio.Queue = asyncio.Queue()

    @client.feature(t.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
    def _diagnostics(params):
        got.put_nowait((time.perf_counter(), len(params.diagnostics)))

    await client.start_io(sys.executable, "-m", "tidyplan", "lsp")
    await client.initialize_async(t.InitializeParams(capabilities=t.ClientCapabilities()))
    client.initialized(t.InitializedParams())
    uri = (REPO / "bench-2000-lines.pddl").as_uri()  # never written: the text is the editor's
    client.text_document_did_open(t.DidOpenTextDocumentParams(t.TextDocumentItem(uri, "pddl", 1, text)))
    await got.get()
    lines = text.splitlines()
    targets = [i for i, line in enumerate(lines) if "(hand-empty)" in line and "(:" not in line]
    times = []
    for k in range(changes):
        line = targets[(k // 2 * 7) % len(targets)]
        col = lines[line].index("(hand-empty)") + 5
        typo = k % 2 == 0  # delete a letter, then put it back
        r = t.Range(t.Position(line, col), t.Position(line, col + 1 if typo else col))
        change = t.TextDocumentContentChangePartial(range=r, text="" if typo else lines[line][col])
        sent = time.perf_counter()
        client.text_document_did_change(
            t.DidChangeTextDocumentParams(t.VersionedTextDocumentIdentifier(version=k + 2, uri=uri), [change])
        )
        at, n = await got.get()
        assert (n > 0) == typo, (k, n)  # the typo is reported, its repair clears it
        times.append((at - sent) * 1000)
    await client.shutdown_async(None)
    client.exit(None)
    await client.stop()
    return times


def in_process(text: str) -> None:
    from tidyplan.editor.workspace import Workspace

    ws = Workspace()
    for what, body in (
        ("cold (open)", text),
        ("after a keystroke", text.replace("(hand-empty)", "(hand-empt)", 1)),
    ):
        t0 = time.perf_counter()
        ws.update("/bench.pddl", body)
        t1 = time.perf_counter()
        ws.diagnostics("/bench.pddl")
        t2 = time.perf_counter()
        print(
            f"  in process, {what}: index {1000 * (t1 - t0):.1f} ms, read and check {1000 * (t2 - t1):.1f} ms"
        )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--changes", type=int, default=40)
    args = ap.parse_args()
    text = big_domain()
    print(f"domain: {text.count(chr(10))} lines, {text.count('(:action')} actions")
    in_process(text)
    times = asyncio.run(through_the_server(text, args.changes))
    print(
        f"change -> diagnostics over stdio, {len(times)} changes: median {statistics.median(times):.1f} ms, "
        f"90th percentile {sorted(times)[int(0.9 * len(times)) - 1]:.1f} ms, worst {max(times):.1f} ms"
    )


if __name__ == "__main__":
    main()
