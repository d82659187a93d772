#!/usr/bin/env python3
"""Checks of `brdffit fit --json` output for the tool tests.

    check_json.py schema OUT [FILE...]
        every line is one JSON object with the required keys first, in
        order, with the documented types; with FILE arguments, there is one
        line per file, in that order.
    check_json.py settings OUT KEY=JSON...
        every line has the keys with the given JSON values (numbers equal to
        1e-12 relative): the settings that shaped the fit are recorded.
    check_json.py near OUT REL NAME=V[:V...]...
        the first line's params match the values within relative tolerance
        REL (NAME=V for a shared parameter, NAME=V1:V2:V3 per channel).
    check_json.py stages OUT CONVERGED KIND[:INDEX]...
        the first line's "converged" is CONVERGED (true or false) and its
        stages are those, in order; every stage is well formed, exactly
        the documented ones are kept, and the last kept stage's stop and
        iterations are the object's.
    check_json.py exports OUT FORMAT:MODEL:REFIT...
        the first line's "exports" (the last key) lists exactly those
        exports, in order (REFIT true or false), each well formed; one that
        is not a refit carries the fit's own error figures.
    check_json.py correlation OUT [HELD...]
        the first line's "correlation" names every entry of the parameter
        vector once (NAME, or NAME_C per channel) and is symmetric, within
        [-1, 1], 1 on the diagonal for every parameter with a positive
        finite standard error and null exactly in the rows and columns of
        the others; the HELD parameters' entries are all null, and some
        correlation between two free parameters is not 0.
"""
import json
import math
import sys

REQUIRED = ["file", "model", "pipeline", "channels", "params", "shader", "errors",
            "iterations", "stop", "fit_ms"]


def fail(msg):
    sys.stderr.write("check_json: %s\n" % msg)
    sys.exit(1)


def is_number(x):
    return isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x)


def numbers(x, n):
    return isinstance(x, list) and len(x) == n and all(is_number(v) for v in x)


def check_object(obj, line_no):
    keys = list(obj.keys())
    if keys[:len(REQUIRED)] != REQUIRED:
        fail("line %d: keys %s, expected %s first" % (line_no, keys, REQUIRED))
    n = obj["channels"]
    checks = [
        (isinstance(obj["file"], str), "file is a string"),
        (isinstance(obj["model"], str), "model is a string"),
        (obj["pipeline"] in ("auto", "joint", "two-stage"), "pipeline is known"),
        (isinstance(n, int) and not isinstance(n, bool) and n >= 1, "channels is a count"),
        (isinstance(obj["params"], dict) and len(obj["params"]) >= 1, "params is an object"),
        (all(is_number(v) or numbers(v, n) for v in obj["params"].values()),
         "params are numbers or per-channel arrays"),
        (obj["shader"] is None or (isinstance(obj["shader"], dict)
                                   and list(obj["shader"].keys()) == ["Rs", "cd", "cs"]
                                   and is_number(obj["shader"]["Rs"])
                                   and numbers(obj["shader"]["cd"], n)
                                   and numbers(obj["shader"]["cs"], n)),
         "shader is null or {Rs, cd[], cs[]}"),
        (isinstance(obj["errors"], dict) and list(obj["errors"].keys()) == ["rms", "ngan", "cost"]
         and all(is_number(v) for v in obj["errors"].values()), "errors is {rms, ngan, cost}"),
        (isinstance(obj["iterations"], int) and obj["iterations"] >= 0, "iterations is a count"),
        (isinstance(obj["stop"], str) and obj["stop"] != "", "stop is a string"),
        (is_number(obj["fit_ms"]) and obj["fit_ms"] >= 0, "fit_ms is a number"),
    ]
    for ok, what in checks:
        if not ok:
            fail("line %d: expected: %s; got %s" % (line_no, what, json.dumps(obj)))


def read_lines(path):
    with open(path, encoding="utf-8") as f:
        lines = f.read().splitlines()
    if not lines:
        fail("no output")
    try:
        return [json.loads(line) for line in lines]
    except ValueError as e:
        fail("not JSON: %s" % e)


def schema(path, files):
    objs = read_lines(path)
    for i, obj in enumerate(objs, 1):
        check_object(obj, i)
    if files and [o["file"] for o in objs] != files:
        fail("files %s, expected %s" % ([o["file"] for o in objs], files))
    print("ok: %d object(s)" % len(objs))


def near(path, rel, specs):
    params = read_lines(path)[0]["params"]
    for spec in specs:
        name, _, text = spec.partition("=")
        want = [float(v) for v in text.split(":")]
        got = params.get(name)
        got = got if isinstance(got, list) else [got]
        if len(got) != len(want):
            fail("%s: %s, expected %s" % (name, got, want))
        for g, w in zip(got, want):
            if not is_number(g) or abs(g - w) > rel * abs(w):
                fail("%s: %r, expected %r within %g relative" % (name, g, w, rel))
    print("ok: %s" % " ".join(specs))


def settings(path, specs):
    for i, obj in enumerate(read_lines(path), 1):
        for spec in specs:
            key, _, text = spec.partition("=")
            want = json.loads(text)
            if key not in obj:
                fail("line %d: no key %s in %s" % (i, key, json.dumps(obj)))
            got = obj[key]
            same = (abs(got - want) <= 1e-12 * abs(want) if is_number(got) and is_number(want)
                    else got == want)
            if not same:
                fail("line %d: %s is %s, expected %s" % (i, key, json.dumps(got), text))
    print("ok: %s" % " ".join(specs))


STAGE_KEYS = ["stage", "index", "kept", "converged", "stop", "iterations", "evaluations",
              "cost", "lambda"]


def check_stage(s, i):
    if list(s.keys()) != STAGE_KEYS:
        fail("stage %d: keys %s, expected %s" % (i, list(s.keys()), STAGE_KEYS))
    n = len(s["cost"])
    if s["stage"] == "scan":
        ok = (n == s["evaluations"] and s["iterations"] == 0 and s["stop"] == "none"
              and not s["kept"] and all(b <= a for a, b in zip(s["cost"], s["cost"][1:])))
    else:
        ok = n == s["iterations"] + 1 and s["evaluations"] >= 1
    if not ok or len(s["lambda"]) != n or not all(is_number(v) for v in s["cost"] + s["lambda"]):
        fail("stage %d is not well formed: %s" % (i, json.dumps(s)))


def stages(path, converged, kinds):
    obj = read_lines(path)[0]
    if obj.get("converged") is not (converged == "true"):
        fail("converged is %r, expected %s" % (obj.get("converged"), converged))
    got = ["%s:%d" % (s["stage"], s["index"]) for s in obj["stages"]]
    want = [k if ":" in k else k + ":0" for k in kinds]
    if got != want:
        fail("stages %s, expected %s" % (got, want))
    for i, s in enumerate(obj["stages"]):
        check_stage(s, i)
    kept = [s for s in obj["stages"] if s["kept"]]
    polishes = [s for s in obj["stages"] if s["stage"] == "polish"]
    if polishes and len(kept) != 1:
        fail("auto keeps exactly one polish, not %d" % len(kept))
    if not polishes and len(kept) != len(obj["stages"]):
        fail("joint and two-stage keep every stage")
    if kept[-1]["stop"] != obj["stop"] or kept[-1]["iterations"] != obj["iterations"]:
        fail("the fit's stop and iterations are not its final stage's")
    print("ok: %s" % " ".join(got))


EXPORT_KEYS = ["format", "file", "model", "refit", "rms", "ngan", "cost"]


def exports(path, specs):
    obj = read_lines(path)[0]
    if list(obj.keys())[-1:] != ["exports"] or not isinstance(obj["exports"], list):
        fail("\"exports\" is not the last key of %s" % json.dumps(obj))
    got = []
    for e in obj["exports"]:
        if (not isinstance(e, dict) or list(e.keys()) != EXPORT_KEYS
                or e["format"] not in ("gltf", "mtlx") or not isinstance(e["file"], str)
                or not isinstance(e["model"], str) or not isinstance(e["refit"], bool)
                or not all(is_number(e[k]) and e[k] >= 0 for k in ("rms", "ngan", "cost"))):
            fail("export not well formed: %s" % json.dumps(e))
        if not e["refit"] and (e["model"] != obj["model"] or
                               [e[k] for k in ("rms", "ngan", "cost")] != list(obj["errors"].values())):
            fail("an export that is not a refit differs from the fit: %s" % json.dumps(e))
        got.append("%s:%s:%s" % (e["format"], e["model"], "true" if e["refit"] else "false"))
    if got != specs:
        fail("exports %s, expected %s" % (got, specs))
    print("ok: exports %s" % " ".join(got))


def correlation(path, held):
    obj = read_lines(path)[0]
    corr, se = obj.get("correlation"), obj["std_errors"]
    if obj.get("std_errors_estimator") not in ("classic", "sandwich"):
        fail("std_errors_estimator is %r" % obj.get("std_errors_estimator"))
    if not isinstance(corr, dict) or list(corr.keys()) != ["names", "matrix"]:
        fail("correlation is not {names, matrix}: %s" % json.dumps(corr))
    names, m = corr["names"], corr["matrix"]
    want = sorted(k if not isinstance(v, list) else "%s_%d" % (k, c)
                  for k, v in se.items() for c in range(len(v) if isinstance(v, list) else 1))
    if sorted(names) != want:
        fail("correlation names %s, expected those of %s" % (names, want))
    p = len(names)
    if not isinstance(m, list) or len(m) != p or any(not isinstance(row, list) or len(row) != p
                                                     for row in m):
        fail("correlation matrix is not %d x %d" % (p, p))

    def std_error(name):
        base, _, c = name.rpartition("_")
        if base in se and isinstance(se[base], list):
            return se[base][int(c)]
        return se[name]

    usable = [is_number(std_error(n)) and std_error(n) > 0 for n in names]
    off = 0
    for i in range(p):
        for j in range(p):
            x = m[i][j]
            if not (usable[i] and usable[j]):
                if x is not None:
                    fail("correlation[%s][%s] = %r, expected null" % (names[i], names[j], x))
                continue
            if not is_number(x) or abs(x) > 1 or x != m[j][i]:
                fail("correlation[%s][%s] = %r, [%s][%s] = %r" % (names[i], names[j], x,
                                                                 names[j], names[i], m[j][i]))
            if i == j and x != 1:
                fail("correlation[%s][%s] = %r, expected 1" % (names[i], names[i], x))
            if i != j and x != 0:
                off += 1
    for i, n in enumerate(names):
        if n.rpartition("_")[0] in held or n in held:
            if usable[i]:
                fail("held parameter %s has a standard error" % n)
    if sum(usable) < 2 or off == 0:
        fail("no correlation between free parameters: %s" % json.dumps(corr))
    print("ok: correlation of %d parameters, %d free" % (p, sum(usable)))


def main(argv):
    if len(argv) >= 3 and argv[1] == "schema":
        schema(argv[2], argv[3:])
    elif len(argv) >= 4 and argv[1] == "settings":
        settings(argv[2], argv[3:])
    elif len(argv) >= 5 and argv[1] == "near":
        near(argv[2], float(argv[3]), argv[4:])
    elif len(argv) >= 5 and argv[1] == "stages":
        stages(argv[2], argv[3], argv[4:])
    elif len(argv) >= 3 and argv[1] == "exports":
        exports(argv[2], argv[3:])
    elif len(argv) >= 3 and argv[1] == "correlation":
        correlation(argv[2], argv[3:])
    else:
        fail("usage: check_json.py schema OUT [FILE...] | near OUT REL NAME=V... | "
             "stages OUT CONVERGED KIND[:INDEX]... | exports OUT FORMAT:MODEL:REFIT... | "
             "correlation OUT [HELD...]")


if __name__ == "__main__":
    main(sys.argv)
