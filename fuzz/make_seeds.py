#!/usr/bin/env python3
"""Seed corpora for the fuzz harnesses, made from examples/ (and the bundled data):
    fuzz/make_seeds.py SOURCE_DIR OUT_DIR   ->  OUT_DIR/<harness>/<seed files>
The server's seeds are raw HTTP requests carrying the examples; the mesh seeds add a cube in
ASCII and binary STL."""
import pathlib
import shutil
import struct
import sys

src, out = pathlib.Path(sys.argv[1]), pathlib.Path(sys.argv[2])


def seeds(harness, files):
    d = out / harness
    d.mkdir(parents=True, exist_ok=True)
    for f in files:
        shutil.copyfile(f, d / f.name)
    return d


def write(harness, name, data):
    d = out / harness
    d.mkdir(parents=True, exist_ok=True)
    (d / name).write_bytes(data)


ex = src / "examples"
seeds("hacks_design_fuzzer", sorted((ex / "hacks").glob("*.yaml")) + sorted((ex / "failing").glob("*.yaml")))
seeds("hacks_part_file_fuzzer", sorted((ex / "parts").glob("*.yaml")) + [src / "hacks/data/parts.yaml"])
seeds("rods_design_fuzzer", sorted((ex / "rods").rglob("*.yaml")))
seeds("flatpack_design_fuzzer", sorted((ex / "flatpack").glob("*.yaml")))
seeds("templates_model_fuzzer", sorted((ex / "templates").glob("*.yaml")) + sorted((src / "templates/data/designs").glob("*.yaml"))[:4])
seeds("mesh_fuzzer", sorted((ex / "parts").glob("*.obj")))

# Inputs that once crashed a harness (fuzz/regressions/<harness>/): every run replays them.
for d in sorted((src / "fuzz" / "regressions").glob("*")):
    if d.is_dir():
        seeds(d.name, sorted(d.iterdir()))

# A unit cube, 12 triangles, as ASCII and binary STL.
v = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]
f = [(0, 2, 1), (0, 3, 2), (4, 5, 6), (4, 6, 7), (0, 1, 5), (0, 5, 4), (1, 2, 6), (1, 6, 5),
     (2, 3, 7), (2, 7, 6), (3, 0, 4), (3, 4, 7)]
ascii = "solid cube\n" + "".join(
    "facet normal 0 0 0\n outer loop\n" + "".join(f"  vertex {v[i][0]} {v[i][1]} {v[i][2]}\n" for i in t) +
    " endloop\nendfacet\n" for t in f) + "endsolid cube\n"
write("mesh_fuzzer", "cube_ascii.stl", ascii.encode())
binary = b"cube".ljust(80, b" ") + struct.pack("<I", len(f)) + b"".join(
    struct.pack("<3f", 0, 0, 0) + b"".join(struct.pack("<3f", *v[i]) for i in t) + b"\0\0" for t in f)
write("mesh_fuzzer", "cube_binary.stl", binary)

# Raw requests, addressed as the harness's server expects (127.0.0.1:8080).
host = b"Host: 127.0.0.1:8080\r\n"


def post(path, body, ctype=b"application/x-yaml", chunked=False):
    head = b"POST " + path + b" HTTP/1.1\r\n" + host + b"Content-Type: " + ctype + b"\r\n"
    if chunked:
        half = len(body) // 2
        parts = [body[:half], body[half:]]
        return head + b"Transfer-Encoding: chunked\r\n\r\n" + b"".join(
            b"%x\r\n" % len(p) + p + b"\r\n" for p in parts) + b"0\r\n\r\n"
    return head + b"Content-Length: %d\r\n\r\n" % len(body) + body


small = (ex / "hacks/basket_between_rods.yaml").read_bytes()
write("server_request_fuzzer", "get_parts.http", b"GET /api/parts HTTP/1.1\r\n" + host + b"\r\n")
write("server_request_fuzzer", "get_mesh.http",
      b"GET /api/parts/ParamTurnbuckle/mesh?extended_length=25 HTTP/1.1\r\n" + host + b"\r\n")
write("server_request_fuzzer", "get_primitive.http",
      b"GET /api/primitives/rod/mesh?radius=5&length=100 HTTP/1.1\r\n" + host + b"\r\n")
write("server_request_fuzzer", "get_design.http", b"GET /api/hacks/design HTTP/1.1\r\n" + host + b"\r\n")
write("server_request_fuzzer", "check.http", post(b"/api/check", small))
write("server_request_fuzzer", "check_chunked.http", post(b"/api/hacks/check", small, chunked=True))
write("server_request_fuzzer", "solve.http", post(b"/api/solve?format=glb", (ex / "hacks/toothbrush_holder.yaml").read_bytes()))
write("server_request_fuzzer", "compatible.http", post(
    b"/api/compatible",
    b'{"a": {"part": "DoubleHook", "primitive": "hook1"}, "b": [{"part": "LongTensionRod", "primitive": "rod"}]}',
    b"application/json"))
