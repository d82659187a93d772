"""Check a glTF asset written by `brdffit fit --gltf` against the fit's JSON
record, independently of the Khronos validator:

    python3 check_gltf.py OUT.gltf FIT.json

The material must hold the fitted parameters exactly (baseColorFactor =
baseColor and alpha 1, metallicFactor = metallic, roughnessFactor =
roughness, and for a gltf-clearcoat fit KHR_materials_clearcoat's
clearcoatFactor and clearcoatRoughnessFactor); the embedded buffer must decode to the declared length; the
positions must lie on the unit sphere with their declared bounds, the
normals equal the positions, and the triangles be non-degenerate, face
outwards and cover the sphere's area. Exits 1 with a message on the first
violation."""
import base64
import json
import math
import struct
import sys

PREFIX = "data:application/octet-stream;base64,"


def fail(what):
    print("check_gltf: " + what)
    sys.exit(1)


def expect(cond, what):
    if not cond:
        fail(what)


def accessor_data(doc, buf, index, fmt, width):
    acc = doc["accessors"][index]
    view = doc["bufferViews"][acc["bufferView"]]
    start = view.get("byteOffset", 0) + acc.get("byteOffset", 0)
    size = struct.calcsize("<" + fmt) * width
    expect(start + size * acc["count"] <= view.get("byteOffset", 0) + view["byteLength"],
           "accessor %d runs past its buffer view" % index)
    return [struct.unpack_from("<" + fmt * width, buf, start + i * size) for i in range(acc["count"])]


def check_coat(doc, fit):
    params = fit["params"]
    ext = doc["materials"][0].get("extensions", {})
    if fit["model"] != "gltf-clearcoat":
        expect(ext == {} and "extensionsUsed" not in doc, "extensions on an uncoated material")
        return
    coat = ext.get("KHR_materials_clearcoat")
    expect(coat is not None, "no KHR_materials_clearcoat on a gltf-clearcoat fit")
    expect(doc.get("extensionsUsed") == ["KHR_materials_clearcoat"], "extensionsUsed is wrong")
    expect(coat["clearcoatFactor"] == params["clearcoat"], "clearcoatFactor differs from the fit")
    expect(coat["clearcoatRoughnessFactor"] == params["clearcoatRoughness"],
           "clearcoatRoughnessFactor differs from the fit")


def check_material(doc, fit):
    params = fit["params"]
    check_coat(doc, fit)
    pbr = doc["materials"][0]["pbrMetallicRoughness"]
    colour = params["baseColor"]
    colour = colour if isinstance(colour, list) else [colour] * 3
    expect(pbr["baseColorFactor"] == colour + [1], "baseColorFactor %s, fitted baseColor %s"
           % (pbr["baseColorFactor"], colour))
    expect(pbr["metallicFactor"] == params["metallic"], "metallicFactor differs from the fit")
    expect(pbr["roughnessFactor"] == params["roughness"], "roughnessFactor differs from the fit")


def check_sphere(doc, buf):
    prim = doc["meshes"][0]["primitives"][0]
    expect(prim.get("mode", 4) == 4, "the primitive is not triangles")
    expect(doc["materials"][prim["material"]] is doc["materials"][0], "mesh without the material")
    pos = accessor_data(doc, buf, prim["attributes"]["POSITION"], "f", 3)
    nrm = accessor_data(doc, buf, prim["attributes"]["NORMAL"], "f", 3)
    idx = [i[0] for i in accessor_data(doc, buf, prim["indices"], "H", 1)]
    acc = doc["accessors"][prim["attributes"]["POSITION"]]
    for q in range(3):
        expect(acc["min"][q] == min(p[q] for p in pos), "POSITION min differs from the data")
        expect(acc["max"][q] == max(p[q] for p in pos), "POSITION max differs from the data")
    for p, n in zip(pos, nrm):
        expect(abs(math.sqrt(sum(x * x for x in p)) - 1.0) < 1e-6, "a vertex off the unit sphere")
        expect(p == n, "a normal that is not the position")
    expect(len(idx) % 3 == 0 and max(idx) < len(pos), "bad triangle indices")
    area = 0.0
    for t in range(0, len(idx), 3):
        a, b, c = (pos[i] for i in idx[t:t + 3])
        u = [b[q] - a[q] for q in range(3)]
        v = [c[q] - a[q] for q in range(3)]
        n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
        twice = math.sqrt(sum(x * x for x in n))
        expect(twice > 1e-9, "degenerate triangle %d" % (t // 3))
        outward = sum(n[q] * (a[q] + b[q] + c[q]) for q in range(3))
        expect(outward > 0.0, "triangle %d faces inwards" % (t // 3))
        area += twice / 2.0
    expect(abs(area / (4.0 * math.pi) - 1.0) < 0.01, "triangles cover %.4f of the sphere's area"
           % (area / (4.0 * math.pi)))
    return len(pos), len(idx) // 3, area


def main():
    with open(sys.argv[1]) as f:
        doc = json.load(f)
    with open(sys.argv[2]) as f:
        fit = json.loads(f.readline())
    expect(doc["asset"]["version"] == "2.0", "asset.version is not 2.0")
    uri = doc["buffers"][0]["uri"]
    expect(uri.startswith(PREFIX), "the buffer is not an embedded base64 data URI")
    buf = base64.b64decode(uri[len(PREFIX):], validate=True)
    expect(len(buf) == doc["buffers"][0]["byteLength"], "buffer length differs from byteLength")
    check_material(doc, fit)
    n_verts, n_tris, area = check_sphere(doc, buf)
    print("check_gltf: material as fitted; %d vertices, %d triangles, area %.5f of 4 pi"
          % (n_verts, n_tris, area / (4.0 * math.pi)))


if __name__ == "__main__":
    main()
