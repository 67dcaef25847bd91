"""The server survives garbage (random bytes in documents, random edits,
requests at random places) and still answers; it exits when stdin closes."""
import os
import random
import subprocess

from conftest import SNELL, open_doc
from lsprotocol import types


async def test_garbage_documents_and_requests(client, tmp_path):
    rng = random.Random(20)
    uri = await open_doc(client, tmp_path / "g.scn", "sphere { radius 1 }\n")
    alphabet = ['{', '}', '<', '>', '"', 'sphere', 'let x = ', 'fn f(', ')', ';', '\n', '/*',
                'import "', 'for i in 0 .. 1e12 {', 'é', '\U0001d6fc', '1e999', 'union {', 'object {']
    text = ""
    for version in range(2, 120):
        if rng.random() < 0.3:
            text = "".join(chr(rng.randrange(1, 0x2FF)) for _ in range(rng.randrange(0, 200)))
        else:
            at = rng.randrange(0, len(text) + 1)
            text = text[:at] + rng.choice(alphabet) + text[at:]
        client.text_document_did_change(
            types.DidChangeTextDocumentParams(
                text_document=types.VersionedTextDocumentIdentifier(uri=uri, version=version),
                content_changes=[types.TextDocumentContentChangeWholeDocument(text=text)],
            )
        )
        pos = types.Position(line=rng.randrange(0, 5), character=rng.randrange(0, 80))
        tid = types.TextDocumentIdentifier(uri=uri)
        await client.text_document_hover_async(types.HoverParams(text_document=tid, position=pos))
        await client.text_document_completion_async(
            types.CompletionParams(text_document=tid, position=pos)
        )
        await client.text_document_definition_async(
            types.DefinitionParams(text_document=tid, position=pos)
        )
        await client.text_document_document_symbol_async(types.DocumentSymbolParams(text_document=tid))
    # Still alive and right.
    client.text_document_did_change(
        types.DidChangeTextDocumentParams(
            text_document=types.VersionedTextDocumentIdentifier(uri=uri, version=500),
            content_changes=[types.TextDocumentContentChangeWholeDocument(text="sphere { radus 1 }\n")],
        )
    )
    await client.wait_for_notification(types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
    assert [d.code for d in client.diagnostics[uri]] == ["UnknownProperty"]


def test_raw_bytes_and_eof():
    """Framing garbage straight on stdin, then EOF: the process exits 0 by itself."""
    rng = random.Random(7)
    junk = bytes(rng.randrange(256) for _ in range(20000))
    body = b'{"jsonrpc":"2.0","id":1,"method":"initialize","params":{"capabilities":{}}}'
    msg = b"Content-Length: %d\r\n\r\n%s" % (len(body), body)
    bad = b"Content-Length: 5\r\n\r\n{{{{{" + b"Content-Length: zz\r\n\r\n"
    p = subprocess.run([SNELL, "lsp"], input=msg + bad + junk + msg, capture_output=True, timeout=30)
    assert p.returncode == 0, p.stderr
    assert p.stdout.count(b'"capabilities"') >= 1


def test_exit_without_shutdown_is_status_1():
    body = b'{"jsonrpc":"2.0","method":"exit"}'
    p = subprocess.run([SNELL, "lsp"], input=b"Content-Length: %d\r\n\r\n%s" % (len(body), body),
                       capture_output=True, timeout=30)
    assert p.returncode == 1


async def test_a_runaway_loop_is_stopped_by_the_step_budget(client, tmp_path):
    import time

    text = "for i in 0 .. 1e12 { sphere { center <i, 0, 0> radius 1 } }\n"
    t0 = time.monotonic()
    uri = await open_doc(client, tmp_path / "loop.scn", text)
    assert "StepBudget" in [d.code for d in client.diagnostics[uri]]
    h = await client.text_document_hover_async(
        types.HoverParams(
            text_document=types.TextDocumentIdentifier(uri=uri),
            position=types.Position(line=0, character=23),
        )
    )
    assert h is not None and "sphere" in h.contents.value
    assert time.monotonic() - t0 < 5  # 5M steps: about 0.2 s here
