"""Check a MaterialX document written by `brdffit fit --mtlx` against the
fit's JSON record:

    python3 check_mtlx.py OUT.mtlx FIT.json

The document must be well-formed XML with a <materialx version="1.39">
root holding one open_pbr_surface (type surfaceshader) and one
surfacematerial whose surfaceshader input names it. Every input of the
shader must be an input of OpenPBR Surface 1.1 with that input's type
(MaterialX libraries/bxdf/open_pbr_surface.mtlx), and the values must be
the mapping of docs/cli.md of the fitted parameters. Exits 1 with a
message on the first violation."""
import json
import sys
import xml.etree.ElementTree as ET

# The OpenPBR Surface 1.1 inputs brdffit may write, with their types.
OPENPBR_INPUTS = {
    "base_weight": "float", "base_color": "color3", "base_metalness": "float",
    "base_diffuse_roughness": "float", "specular_weight": "float",
    "specular_color": "color3", "specular_roughness": "float", "specular_ior": "float",
    "coat_weight": "float", "coat_color": "color3", "coat_roughness": "float",
    "coat_ior": "float", "coat_darkening": "float",
}


def fail(what):
    print("check_mtlx: " + what)
    sys.exit(1)


def expect(cond, what):
    if not cond:
        fail(what)


def close(a, b):
    return abs(a - b) <= 1e-8 * max(abs(b), 1e-3)


def expected_values(fit):
    p = fit["params"]
    colour = p["baseColor"] if isinstance(p["baseColor"], list) else [p["baseColor"]] * 3
    want = {"base_weight": [1.0], "base_color": colour, "base_metalness": [p["metallic"]],
            "base_diffuse_roughness": [0.0], "specular_weight": [1.0],
            "specular_color": [1.0, 1.0, 1.0], "specular_roughness": [p["roughness"]],
            "specular_ior": [1.5], "coat_weight": [p.get("clearcoat", 0.0)]}
    if fit["model"] == "gltf-clearcoat":
        want.update({"coat_color": [1.0, 1.0, 1.0], "coat_roughness": [p["clearcoatRoughness"]],
                     "coat_ior": [1.5], "coat_darkening": [0.0]})
    return want


def main():
    try:
        root = ET.parse(sys.argv[1]).getroot()
    except ET.ParseError as e:
        fail("not well-formed XML: %s" % e)
    with open(sys.argv[2]) as f:
        fit = json.loads(f.readline())
    expect(root.tag == "materialx" and root.get("version") == "1.39", "root is not materialx 1.39")
    shaders = root.findall("open_pbr_surface")
    materials = root.findall("surfacematerial")
    expect(len(shaders) == 1 and len(materials) == 1, "need one shader and one material")
    shader = shaders[0]
    expect(shader.get("type") == "surfaceshader", "open_pbr_surface is not a surfaceshader")
    link = materials[0].findall("input")
    expect(len(link) == 1 and link[0].get("name") == "surfaceshader" and
           link[0].get("nodename") == shader.get("name"), "the material does not use the shader")
    got = {}
    for i in shader.findall("input"):
        name, kind = i.get("name"), i.get("type")
        expect(OPENPBR_INPUTS.get(name) == kind, "%s (%s) is not an OpenPBR 1.1 input" % (name, kind))
        got[name] = [float(x) for x in i.get("value").split(",")]
    want = expected_values(fit)
    expect(sorted(got) == sorted(want), "inputs %s, expected %s" % (sorted(got), sorted(want)))
    for name, values in want.items():
        expect(len(got[name]) == len(values) and all(map(close, got[name], values)),
               "%s is %s, the fit gives %s" % (name, got[name], values))
    print("check_mtlx: %s with %d inputs as fitted" % (shader.get("name"), len(got)))


if __name__ == "__main__":
    main()
