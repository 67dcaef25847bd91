"""Diagnostics: exact ranges, severities, [Kind] codes, notes as related
information, debounced updates on change, and imports from unsaved buffers."""
from conftest import find, open_doc
from lsprotocol import types


def errors(diags):
    """The errors alone (a scene without a light also has snell check's warning)."""
    return [d for d in diags if d.severity == types.DiagnosticSeverity.Error]


async def test_unknown_property_range_code_and_note(client, tmp_path):
    text = "camera { location <0, 1, -5> look_at <0, 1, 0> }\nsphere { radus 1 }\n"
    uri = await open_doc(client, tmp_path / "a.scn", text)
    diags = client.diagnostics[uri]
    assert len(diags) >= 1
    d = diags[0]
    assert d.severity == types.DiagnosticSeverity.Error
    assert d.code == "UnknownProperty"
    assert d.source == "snell"
    assert d.range.start == find(text, "radus")
    assert d.range.end == find(text, "radus", delta=5)
    notes = [r.message for r in d.related_information or []]
    assert any("radius" in n for n in notes), notes


async def test_syntax_error_and_warning_severity(client, tmp_path):
    text = "let x = (1 + ;\n"
    uri = await open_doc(client, tmp_path / "b.scn", text)
    codes = [d.code for d in client.diagnostics[uri]]
    assert "ExpectedExpression" in codes, codes
    # A warning: a material that gives back more light than it gets.
    text2 = "sphere { radius 1 material mirror 1.2 }\n"
    uri2 = await open_doc(client, tmp_path / "c.scn", text2)
    sev = {d.code: d.severity for d in client.diagnostics[uri2]}
    assert sev.get("EnergyGain") == types.DiagnosticSeverity.Warning, sev


async def test_change_updates_diagnostics(client, tmp_path):
    text = "sphere { radius -1 }\n"
    uri = await open_doc(client, tmp_path / "d.scn", text)
    assert [d.code for d in client.diagnostics[uri]] == ["InvalidValue"]
    client.text_document_did_change(
        types.DidChangeTextDocumentParams(
            text_document=types.VersionedTextDocumentIdentifier(uri=uri, version=2),
            content_changes=[
                types.TextDocumentContentChangeWholeDocument(
                    text="point_light { position <0, 5, 0> intensity 10 }\n"
                    "sphere { radius 1 center <0, 0, 5> }\n"
                )
            ],
        )
    )
    await client.wait_for_notification(types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
    assert list(client.diagnostics[uri]) == []


async def test_scene_warnings_as_snell_check_prints_them(client, tmp_path):
    # No light for a diffuse sphere, and the camera (at the origin) inside it:
    # `snell check`'s two warnings, at the sphere.
    text = "camera { location <0, 0, 0> look_at <0, 0, 1> }\nsphere { radius 2 }\n"
    uri = await open_doc(client, tmp_path / "w.scn", text)
    diags = [d for d in client.diagnostics[uri] if d.code == "SceneWarning"]
    messages = sorted(d.message for d in diags)
    assert len(diags) == 2, messages
    assert messages[0].startswith("the camera at <0, 0, 0> is inside the sphere")
    assert messages[1].startswith("the scene has no light")
    for d in diags:
        assert d.severity == types.DiagnosticSeverity.Warning
        assert d.range.start == find(text, "sphere")
        assert d.range.end == find(text, "sphere", delta=6)


async def test_unsaved_import_wins_over_disk(client, tmp_path):
    (tmp_path / "lib.scn").write_text("let size = 1;\n")
    main = 'import "lib.scn";\nsphere { radius size }\n'
    # The open, unsaved lib.scn says size is negative: the main scene sees that.
    await open_doc(client, tmp_path / "lib.scn", "let size = -2;\n")
    uri = await open_doc(client, tmp_path / "main.scn", main)
    codes = [d.code for d in client.diagnostics[uri]]
    assert codes == ["InvalidValue"], codes


async def test_error_in_an_import_shows_at_the_import(client, tmp_path):
    (tmp_path / "broken.scn").write_text("let a = ;\n")
    text = 'import "broken.scn";\nsphere { radius 1 }\n'
    uri = await open_doc(client, tmp_path / "m.scn", text)
    diags = client.diagnostics[uri]
    assert len(diags) == 1
    d = diags[0]
    assert d.code == "ExpectedExpression"
    assert d.range.start == find(text, '"broken.scn"')
    assert "broken.scn:1:9" in d.message
    where = d.related_information[0].location
    assert where.uri == (tmp_path / "broken.scn").as_uri()
    assert where.range.start == types.Position(line=0, character=8)


async def test_utf16_columns(client, tmp_path):
    # é is one UTF-16 unit (two bytes), 𝛼 two units (four bytes).
    text = 'let s = "é𝛼"; sphere { radus 1 }\n'
    uri = await open_doc(client, tmp_path / "u.scn", text)
    d = client.diagnostics[uri][0]
    col = text.index("radus") + 1  # + 1: the astral letter counts twice
    assert d.range.start == types.Position(line=0, character=col)
    assert d.range.end == types.Position(line=0, character=col + 5)


async def test_an_import_changed_on_disk(client, tmp_path):
    lib = tmp_path / "lib2.scn"
    lib.write_text("let size = 1;\n")
    uri = await open_doc(client, tmp_path / "w.scn", 'import "lib2.scn";\nsphere { radius size }\n')
    assert errors(client.diagnostics[uri]) == []
    lib.write_text("let size = -1;\n")
    client.workspace_did_change_watched_files(
        types.DidChangeWatchedFilesParams(
            changes=[types.FileEvent(uri=lib.as_uri(), type=types.FileChangeType.Changed)]
        )
    )
    await client.wait_for_notification(types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
    assert [d.code for d in client.diagnostics[uri]] == ["InvalidValue"]


def png_bytes(w: int, h: int) -> bytes:
    """A w×h grey 8-bit RGB PNG, written by hand (zlib and CRCs)."""
    import struct
    import zlib

    def chunk(kind: bytes, data: bytes) -> bytes:
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))

    rows = b"".join(b"\0" + bytes([(x * 37 + y * 11) % 256 for x in range(w * 3)]) for y in range(h))
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(rows)) + chunk(b"IEND", b""))


async def test_an_unreadable_image_beside_other_errors(client, tmp_path):
    # §17: an image cut short passes the compiler's checks (it exists, its first
    # bytes are a PNG's) and fails only when read: shown as `check` shows it, at its
    # `file`, beside the scene's other errors (§10); fixed on disk, it is gone.
    good = png_bytes(32, 32)
    (tmp_path / "cut.png").write_bytes(good[: len(good) // 2])
    text = 'sphere { material diffuse image { file "cut.png" } }\ntorus { major 1 minor 3 }\n'
    uri = await open_doc(client, tmp_path / "img.scn", text)
    diags = client.diagnostics[uri]
    codes = sorted(d.code for d in diags)
    assert codes == ["FileUnreadable", "InvalidValue"], codes
    d = next(d for d in diags if d.code == "FileUnreadable")
    assert d.range.start == find(text, '"cut.png"')
    assert d.range.end == find(text, '"cut.png"', delta=9)
    assert "cannot read image" in d.message, d.message
    (tmp_path / "cut.png").write_bytes(good)
    client.text_document_did_change(
        types.DidChangeTextDocumentParams(
            text_document=types.VersionedTextDocumentIdentifier(uri=uri, version=2),
            content_changes=[types.TextDocumentContentChangeWholeDocument(text=text.replace("3", "0.3"))],
        )
    )
    await client.wait_for_notification(types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
    assert errors(client.diagnostics[uri]) == []
