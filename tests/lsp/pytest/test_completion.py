"""Completion: statement level, properties of the enclosing block (only those
not yet given), values (names in scope, constructors, builtins), imports."""
from conftest import find, open_doc
from lsprotocol import types


async def labels(client, uri, pos):
    r = await client.text_document_completion_async(
        types.CompletionParams(text_document=types.TextDocumentIdentifier(uri=uri), position=pos)
    )
    items = r.items if isinstance(r, types.CompletionList) else r
    return {i.label for i in items}


async def test_statement_level(client, tmp_path):
    text = "let r = 1;\n\n"
    uri = await open_doc(client, tmp_path / "s.scn", text)
    got = await labels(client, uri, types.Position(line=1, character=0))
    assert {"sphere", "camera", "settings", "union", "let", "fn", "import", "r"} <= got
    assert "radius" not in got


async def test_properties_not_yet_given(client, tmp_path):
    text = "sphere { center <0, 0, 0>  }\n"
    uri = await open_doc(client, tmp_path / "p.scn", text)
    got = await labels(client, uri, find(text, "  }", delta=1))
    assert "radius" in got and "material" in got and "translate" in got
    assert "center" not in got  # already given
    assert "camera" not in got  # not a statement here
    # A transform may repeat.
    text2 = "box { min <0,0,0> max <1,1,1> translate <1, 0, 0>  }\n"
    uri2 = await open_doc(client, tmp_path / "q.scn", text2)
    got = await labels(client, uri2, find(text2, "  }", delta=1))
    assert "translate" in got and "min" not in got
    # Properties after the cursor are given too; a nested block's are not its parent's.
    text3 = "sphere { radius 1  center <0, 0, 0> material diffuse { color 1 } }\n"
    uri3 = await open_doc(client, tmp_path / "r.scn", text3)
    got = await labels(client, uri3, find(text3, "  center", delta=1))
    assert "center" not in got and "radius" not in got and "material" not in got
    assert "translate" in got


async def test_values(client, tmp_path):
    text = "let glass = dielectric 1.5;\nsphere { material  }\n"
    uri = await open_doc(client, tmp_path / "v.scn", text)
    got = await labels(client, uri, find(text, "material ", delta=9))
    assert {"glass", "diffuse", "mirror", "dielectric", "sin", "true"} <= got
    assert "radius" not in got


async def test_typing_a_word(client, tmp_path):
    text = "sphere { rad }\n"
    uri = await open_doc(client, tmp_path / "w.scn", text)
    got = await labels(client, uri, find(text, "rad", delta=3))
    assert "radius" in got


async def test_imports(client, tmp_path):
    (tmp_path / "mine.scn").write_text("let a = 1;\n")
    text = 'import "\n'
    uri = await open_doc(client, tmp_path / "i.scn", text)
    got = await labels(client, uri, types.Position(line=0, character=8))
    assert "mine.scn" in got  # beside the file
    assert "colors.scn" in got and "materials.scn" in got  # the standard library
    assert "i.scn" not in got  # never itself


async def test_nested_and_group_blocks(client, tmp_path):
    text = "union {\n  sphere { radius 1 }\n  \n}\nbox { min <0,0,0> max <1,1,1> motion {  } }\n"
    uri = await open_doc(client, tmp_path / "n.scn", text)
    # In a CSG body: statements and the object properties.
    got = await labels(client, uri, types.Position(line=2, character=2))
    assert {"sphere", "let", "translate", "material"} <= got
    # In motion { }: only motion's properties.
    got = await labels(client, uri, find(text, "{  }", delta=2))
    assert {"translate", "rotate", "scale"} <= got
    assert "min" not in got and "material" not in got


async def test_enum_spellings_in_strings(client, tmp_path):
    text = 'settings { sampler "" }\n'
    uri = await open_doc(client, tmp_path / "e.scn", text)
    got = await labels(client, uri, find(text, '""', delta=1))
    assert "stratified" in got  # runtime/ir/kinds.def's SamplerKind


async def test_nothing_inside_comments(client, tmp_path):
    # Inside a /* */ comment (closed or not) as inside a // one: no items (a block
    # comment offered the statement keywords, or the block's properties).
    for text, marker in [
        ("/* sphere {  */\n", "{ "),
        ("sphere { radius 1 } /* radius  */\n", "radius  "),
        ("sphere { /*  */ }\n", "/* "),
        ("/* sphere {  \n", "{ "),
        ("// sphere {  \n", "{ "),
    ]:
        uri = await open_doc(client, tmp_path / "c.scn", text)
        got = await labels(client, uri, find(text, marker, delta=len(marker)))
        assert got == set(), text
    # After a closed comment, completion is back.
    text = "/* note */ \n"
    uri = await open_doc(client, tmp_path / "d.scn", text)
    assert "sphere" in await labels(client, uri, types.Position(line=0, character=11))


async def test_csg_body_offers_what_it_holds(client, tmp_path):
    # §12: a CSG body holds objects (and let, for, if, calls, imports): settings,
    # the camera, lights and the background there are errors, so not offered.
    text = "union {\n  sphere { radius 1 }\n  \n}\n"
    uri = await open_doc(client, tmp_path / "g.scn", text)
    got = await labels(client, uri, types.Position(line=2, character=2))
    assert {"sphere", "box", "union", "object", "let", "for", "import"} <= got
    assert not got & {"settings", "camera", "point_light", "area_light", "background"}


async def test_import_items_replace_what_is_typed(client, tmp_path):
    # Each item's textEdit covers the text typed inside the quotes, so a client
    # never doubles it ("colors.colors.scn").
    text = 'import "colors.\n'
    uri = await open_doc(client, tmp_path / "t.scn", text)
    r = await client.text_document_completion_async(
        types.CompletionParams(
            text_document=types.TextDocumentIdentifier(uri=uri),
            position=types.Position(line=0, character=15),
        )
    )
    items = r.items if isinstance(r, types.CompletionList) else r
    colors = [i for i in items if i.label == "colors.scn"]
    assert colors
    edit = colors[0].text_edit
    assert edit.new_text == "colors.scn"
    assert (edit.range.start.line, edit.range.start.character) == (0, 8)
    assert (edit.range.end.line, edit.range.end.character) == (0, 15)


async def test_import_offers_open_unsaved_documents(client, tmp_path):
    # An open document counts for imports before it is saved, so completion offers
    # it beside the files on disk (not itself).
    await open_doc(client, tmp_path / "unsaved_lib.scn", "let k = 1;\n")
    text = 'import "\n'
    uri = await open_doc(client, tmp_path / "main.scn", text)
    got = await labels(client, uri, types.Position(line=0, character=8))
    assert "unsaved_lib.scn" in got
    assert "main.scn" not in got
    assert not (tmp_path / "unsaved_lib.scn").exists()
