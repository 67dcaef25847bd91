"""pytest-lsp fixtures: `snell lsp` (SNELL_EXE) under a client that announces
VS Code's capabilities, and helpers to open documents and read positions."""
import os
import pathlib
import sys

import pytest
import pytest_lsp
from lsprotocol import types
from pytest_lsp import ClientServerConfig, LanguageClient, client_capabilities

SNELL = os.environ.get("SNELL_EXE", "snell")


@pytest_lsp.fixture(config=ClientServerConfig(server_command=[SNELL, "lsp"]))
async def client(lsp_client: LanguageClient):
    await lsp_client.initialize_session(
        types.InitializeParams(capabilities=client_capabilities("visual-studio-code"))
    )
    yield
    await lsp_client.shutdown_session()


def find(text: str, needle: str, nth: int = 0, delta: int = 0) -> types.Position:
    """The LSP position of the nth `needle` in `text` (plus `delta` columns);
    the test scenes are ASCII, so UTF-16 columns are characters."""
    at = -1
    for _ in range(nth + 1):
        at = text.index(needle, at + 1)
    at += delta
    line = text.count("\n", 0, at)
    col = at - (text.rfind("\n", 0, at) + 1)
    return types.Position(line=line, character=col)


async def open_doc(client: LanguageClient, path: pathlib.Path, text: str, wait: bool = True):
    uri = path.as_uri()
    client.text_document_did_open(
        types.DidOpenTextDocumentParams(
            text_document=types.TextDocumentItem(
                uri=uri, language_id="snell", version=1, text=text
            )
        )
    )
    if wait:
        await client.wait_for_notification(types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
    return uri
