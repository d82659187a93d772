"""Check a MaterialX document written by `brdffit fit --mtlx` against the
fit's JSON record:

    python3 check_mtlx.py OUT.mtlx FIT.json [SHADERS]

The document must be well-formed XML with a <materialx version="1.39">
root holding the shader nodes SHADERS names (comma-separated, default
open_pbr_surface; open_pbr_surface and/or standard_surface), one of each,
of type surfaceshader, each with one surfacematerial whose surfaceshader
input names it. Every input of a shader must be an input of that shader
(OpenPBR Surface 1.1 or Autodesk Standard Surface) with that input's type
(MaterialX libraries/bxdf/open_pbr_surface.mtlx and standard_surface.mtlx),
and the values must be the mapping of docs/cli.md of the fitted
parameters. Exits 1 with a message on the first violation."""
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

# The Autodesk Standard Surface inputs brdffit may write, with their types.
STANDARD_INPUTS = {
    "base": "float", "base_color": "color3", "diffuse_roughness": "float",
    "metalness": "float", "specular": "float", "specular_color": "color3",
    "specular_roughness": "float", "specular_IOR": "float", "coat": "float",
    "coat_color": "color3", "coat_roughness": "float", "coat_IOR": "float",
    "coat_affect_color": "float", "coat_affect_roughness": "float",
}

SHADER_INPUTS = {"open_pbr_surface": OPENPBR_INPUTS, "standard_surface": STANDARD_INPUTS}
SHADER_TITLES = {"open_pbr_surface": "an OpenPBR 1.1", "standard_surface": "a Standard Surface"}


def fail(what):
    print("check_mtlx: " + what)
    sys.exit(1)


def expect(cond, what):
    if not cond:
        fail(what)


def close(a, b):
    return abs(a - b) <= 1e-8 * max(abs(b), 1e-3)


def fitted_material(fit):
    """The material of a fit record: glTF's parameters (ior 1.5 for the
    base and the coat) or OpenPBR's own (docs/models.md)."""
    p = fit["params"]
    if fit["model"].startswith("gltf"):
        m = {"color": p["baseColor"], "metal": p["metallic"], "rough": p["roughness"], "ior": 1.5,
             "coated": fit["model"] == "gltf-clearcoat", "coat": p.get("clearcoat", 0.0),
             "coat_rough": p.get("clearcoatRoughness", 0.0), "coat_ior": 1.5}
    else:
        m = {"color": p["base_color"], "metal": p["base_metalness"],
             "rough": p["specular_roughness"], "ior": p["specular_ior"],
             "coated": "coat_weight" in p, "coat": p.get("coat_weight", 0.0),
             "coat_rough": p.get("coat_roughness", 0.0), "coat_ior": p.get("coat_ior", 1.6)}
    if not isinstance(m["color"], list):
        m["color"] = [m["color"]] * 3
    return m


def expected_values(fit, shader):
    m = fitted_material(fit)
    white = [1.0, 1.0, 1.0]
    if shader == "open_pbr_surface":
        want = {"base_weight": [1.0], "base_color": m["color"], "base_metalness": [m["metal"]],
                "base_diffuse_roughness": [0.0], "specular_weight": [1.0],
                "specular_color": white, "specular_roughness": [m["rough"]],
                "specular_ior": [m["ior"]], "coat_weight": [m["coat"]]}
        if m["coated"]:
            want.update({"coat_color": white, "coat_roughness": [m["coat_rough"]],
                         "coat_ior": [m["coat_ior"]], "coat_darkening": [0.0]})
    else:
        want = {"base": [1.0], "base_color": m["color"], "metalness": [m["metal"]],
                "diffuse_roughness": [0.0], "specular": [1.0], "specular_color": white,
                "specular_roughness": [m["rough"]], "specular_IOR": [m["ior"]],
                "coat": [m["coat"]]}
        if m["coated"]:
            want.update({"coat_color": white, "coat_roughness": [m["coat_rough"]],
                         "coat_IOR": [m["coat_ior"]], "coat_affect_color": [0.0],
                         "coat_affect_roughness": [0.0]})
    return want


def check_shader(root, fit, kind):
    shaders = root.findall(kind)
    expect(len(shaders) == 1, "need one %s, found %d" % (kind, len(shaders)))
    shader = shaders[0]
    expect(shader.get("type") == "surfaceshader", "%s is not a surfaceshader" % kind)
    users = [m for m in root.findall("surfacematerial")
             if any(i.get("name") == "surfaceshader" and i.get("nodename") == shader.get("name")
                    for i in m.findall("input"))]
    expect(len(users) == 1 and len(users[0].findall("input")) == 1,
           "no single material uses %s" % shader.get("name"))
    got = {}
    for i in shader.findall("input"):
        name, typ = i.get("name"), i.get("type")
        expect(SHADER_INPUTS[kind].get(name) == typ,
               "%s (%s) is not %s input" % (name, typ, SHADER_TITLES[kind]))
        got[name] = [float(x) for x in i.get("value").split(",")]
    want = expected_values(fit, kind)
    expect(sorted(got) == sorted(want), "inputs %s, expected %s" % (sorted(got), sorted(want)))
    for name, values in want.items():
        expect(len(got[name]) == len(values) and all(map(close, got[name], values)),
               "%s is %s, the fit gives %s" % (name, got[name], values))
    print("check_mtlx: %s with %d inputs as fitted" % (shader.get("name"), len(got)))


def main():
    try:
        root = ET.parse(sys.argv[1]).getroot()
    except ET.ParseError as e:
        fail("not well-formed XML: %s" % e)
    with open(sys.argv[2]) as f:
        fit = json.loads(f.readline())
    kinds = (sys.argv[3] if len(sys.argv) > 3 else "open_pbr_surface").split(",")
    expect(root.tag == "materialx" and root.get("version") == "1.39", "root is not materialx 1.39")
    expect(len(root.findall("surfacematerial")) == len(kinds),
           "need %d materials, found %d" % (len(kinds), len(root.findall("surfacematerial"))))
    for other in SHADER_INPUTS:
        if other not in kinds:
            expect(not root.findall(other), "unexpected %s" % other)
    for kind in kinds:
        check_shader(root, fit, kind)


if __name__ == "__main__":
    main()
