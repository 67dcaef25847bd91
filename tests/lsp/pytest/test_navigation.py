"""Hover, go to definition and document symbols."""
from conftest import find, open_doc
from lsprotocol import types

SCENE = """import "lib.scn";
let r = 1.5;
fn pillar(x, h) { box { min <x - 0.2, 0, -0.2> max <x + 0.2, h, 0.2> } }
for i in 0 .. 3 { pillar(i * 1.5, r); }
sphere { center <0, 1, 0> radius r material shiny }
"""
LIB = "let shiny = mirror 0.9;\n"


async def setup(client, tmp_path):
    (tmp_path / "lib.scn").write_text(LIB)
    return await open_doc(client, tmp_path / "scene.scn", SCENE)


def doc(uri):
    return types.TextDocumentIdentifier(uri=uri)


async def hover_text(client, uri, pos):
    h = await client.text_document_hover_async(types.HoverParams(text_document=doc(uri), position=pos))
    assert h is not None
    return h.contents.value


async def test_hover_property_from_table(client, tmp_path):
    uri = await setup(client, tmp_path)
    text = await hover_text(client, uri, find(SCENE, "radius", delta=2))
    assert "property of `sphere`" in text
    assert "a number > 0" in text  # compile::describe: type and range
    assert "default: `1`" in text  # the IR's default
    text = await hover_text(client, uri, find(SCENE, "min", delta=1))
    assert "required" in text


async def test_hover_defaults_of_named_and_computed_properties(client, tmp_path):
    # §16's highlight properties are named-only; their defaults are the IR's (0 and
    # 50), and the focal distance's is computed: none is "no default".
    text = ("camera { location <0, 1, -5> look_at <0, 1, 0> focal_distance 5 }\n"
            "sphere { material diffuse { color 0.5 specular 0.3 shininess 20 } }\n")
    uri = await open_doc(client, tmp_path / "named.scn", text)
    assert "default: `0`" in await hover_text(client, uri, find(text, "specular", delta=2))
    assert "default: `50`" in await hover_text(client, uri, find(text, "shininess", delta=2))
    focal = await hover_text(client, uri, find(text, "focal_distance", delta=2))
    assert "|look_at - location|" in focal, focal


async def test_hover_block(client, tmp_path):
    uri = await setup(client, tmp_path)
    text = await hover_text(client, uri, find(SCENE, "sphere", delta=1))
    assert "**sphere**" in text and "`center`" in text and "`radius`" in text
    assert "`material`" in text  # the object properties


async def test_hover_names(client, tmp_path):
    uri = await setup(client, tmp_path)
    text = await hover_text(client, uri, find(SCENE, "radius r", delta=7))
    assert "let r" in text and "number" in text and "1.5" in text and "line 2" in text
    text = await hover_text(client, uri, find(SCENE, "shiny", delta=1))
    assert "let shiny" in text and "material" in text and "lib.scn:1" in text
    text = await hover_text(client, uri, find(SCENE, "pillar(i", delta=1))
    assert "fn pillar(x, h)" in text
    text = await hover_text(client, uri, find(SCENE, "h, 0.2"))
    assert "parameter of pillar" in text and "number" in text


async def test_definition(client, tmp_path):
    uri = await setup(client, tmp_path)
    loc = await client.text_document_definition_async(
        types.DefinitionParams(text_document=doc(uri), position=find(SCENE, "radius r", delta=7))
    )
    loc = loc[0] if isinstance(loc, list) else loc
    assert loc.uri == uri
    assert loc.range.start == find(SCENE, "r = 1.5")
    # Into the imported file.
    loc = await client.text_document_definition_async(
        types.DefinitionParams(text_document=doc(uri), position=find(SCENE, "shiny", delta=2))
    )
    loc = loc[0] if isinstance(loc, list) else loc
    assert loc.uri == (tmp_path / "lib.scn").as_uri()
    assert loc.range.start == types.Position(line=0, character=4)
    # The import itself opens the file.
    loc = await client.text_document_definition_async(
        types.DefinitionParams(text_document=doc(uri), position=find(SCENE, "lib.scn", delta=2))
    )
    loc = loc[0] if isinstance(loc, list) else loc
    assert loc.uri == (tmp_path / "lib.scn").as_uri()
    # A parameter.
    loc = await client.text_document_definition_async(
        types.DefinitionParams(text_document=doc(uri), position=find(SCENE, "x + 0.2"))
    )
    loc = loc[0] if isinstance(loc, list) else loc
    assert loc.range.start == find(SCENE, "x, h")


async def test_document_symbols(client, tmp_path):
    uri = await setup(client, tmp_path)
    syms = await client.text_document_document_symbol_async(
        types.DocumentSymbolParams(text_document=doc(uri))
    )
    names = [(s.name, s.kind) for s in syms]
    assert ("r", types.SymbolKind.Variable) in names
    assert ("pillar", types.SymbolKind.Function) in names
    assert ("sphere", types.SymbolKind.Object) in names
    pillar = next(s for s in syms if s.name == "pillar")
    assert [c.name for c in pillar.children] == ["box"]
    assert pillar.selection_range.start == find(SCENE, "pillar")


async def test_document_symbols_of_an_expression_bodied_fn(client, tmp_path):
    text = "fn mk(n) = union { sphere { radius n } box { min 0 max 1 } };\n"
    uri = await open_doc(client, tmp_path / "e.scn", text)
    syms = await client.text_document_document_symbol_async(
        types.DocumentSymbolParams(text_document=doc(uri))
    )
    mk = next(s for s in syms if s.name == "mk")
    assert [c.name for c in mk.children] == ["union"]
    assert [c.name for c in mk.children[0].children] == ["sphere", "box"]


async def test_hover_in_groups_and_constructors(client, tmp_path):
    text = "union {\n  sphere { radius 1 }\n  translate <0, 1, 0>\n}\nlet g = dielectric { ior 1.5 };\n"
    uri = await open_doc(client, tmp_path / "h.scn", text)
    t = await hover_text(client, uri, find(text, "translate", delta=2))
    assert "property of `object`" in t and "may repeat" in t
    t = await hover_text(client, uri, find(text, "ior", delta=1))
    assert "property of `dielectric`" in t
    t = await hover_text(client, uri, find(text, "dielectric", delta=1))
    assert "material constructor" in t
    t = await hover_text(client, uri, find(text, "union", delta=1))
    assert "CSG" in t


async def test_names_in_if_branches(client, tmp_path):
    # The conditions of an if come before its branches in the tree's walk, not in the text.
    text = "let a = 1;\nlet b = 2;\nif a > 0 { sphere { radius b } } else if b > 0 { sphere { radius a } }\n"
    uri = await open_doc(client, tmp_path / "if.scn", text)
    for needle, target in (("radius b", "b = 2"), ("radius a", "a = 1"), ("b > 0", "b = 2")):
        delta = 7 if needle.startswith("radius") else 0
        loc = await client.text_document_definition_async(
            types.DefinitionParams(text_document=doc(uri), position=find(text, needle, delta=delta))
        )
        loc = loc[0] if isinstance(loc, list) else loc
        assert loc.range.start == find(text, target), needle


async def test_hover_background_and_sky_gradient(client, tmp_path):
    text = "background sky_gradient\nsphere { }\n"
    uri = await open_doc(client, tmp_path / "bg.scn", text)
    kw = await hover_text(client, uri, find(text, "background", delta=2))
    assert "background" in kw and "§" in kw, kw
    sky = await hover_text(client, uri, find(text, "sky_gradient", delta=3))
    assert "sky_gradient" in sky and "predeclared" in sky, sky
