"""Frame times of the rasterizer on the canonical scene of ``shared/bench/SCENE.md``, against Mesa's llvmpipe.

What is measured (2 threads by default, ``--threads 1,2`` for both; interleaved with the peer in the same
run, median of ``--frames`` frames after ``--warmup`` frames; the load average is recorded with every row):

- brdfpy: ``Scene.render`` of ``icosphere(L)``, L = 5, 7, 8 (20k, 330k, 1.3M triangles) at 1920×1080, Phong
  shading, with SCENE.md's exact classic Blinn-Phong material (``blinn_phong_classic``, ambient 0.05·kd)
  and its two lights; the same with a Cook-Torrance material (GGX, height-correlated Smith, Schlick F0 0.04,
  kd (0.8, 0.3, 0.2), α 0.3); the 70k Stanford bunny from ``shared/assets`` (skipped if absent). "frame" is
  what a script gets by default: the render (8-bit image and depth) plus ``Image.rgb``. The ratio is
  brdfpy's frame over llvmpipe's draw + read-back; the target of issue 8 is ≤ 0.8 at every mesh, 2 threads.
- the default ``brdfpy render`` scene (cow, sphere, torus on a floor, three lights, 1280×720, 4 samples,
  shadows and obscurance: what the command draws with ``--ao``), brdfpy only: the first frame (which builds
  the BVH and the per-vertex obscurance) and the following ones (which reuse them).
- llvmpipe (OpenGL 4.5, surfaceless EGL, moderngl), one worker process per thread count
  (``LP_NUM_THREADS``), the same vertex data, GLSL computing the same formula per fragment; "frame" is the
  draw, ``glFinish`` and the read-back of the RGBA8 image (also reported without the read-back).
- the NumPy reference rasterizer of ``tests/raster_oracle`` (when present) at a small size, per pixel.

It also checks SCENE.md's check values (centre pixel, the highlight and unlit points, coverage) and the
agreement of brdfpy's image with llvmpipe's and with the ray-cast ideal sphere at 640×480 from icosphere(6)
(mean and max 8-bit difference inside the sphere, silhouette pixels covered by one and not the other).

The peer is optional: ``--install-peers`` installs the Debian packages and moderngl if missing; without it
the llvmpipe part is skipped with a message. Run through ``python benchmarks/run.py render`` or directly.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
ASSETS = ROOT.parent / "shared" / "assets" / "meshes"
DEB_PACKAGES = ("libegl1", "libgl1", "libegl-mesa0", "libgl1-mesa-dri", "libgles2")
GL_ENV = {"LIBGL_ALWAYS_SOFTWARE": "1", "GALLIUM_DRIVER": "llvmpipe", "EGL_PLATFORM": "surfaceless"}

KD = (0.8, 0.3, 0.2)
CT_PARAMS: dict[str, Any] = {"kd": KD, "ks": 1.0, "roughness": 0.3, "f0": 0.04}
# SCENE.md "Check values": (P = N, linear colour, 8-bit) and the ideal sphere's coverage at 1080p.
CHECKS = [
    ((0.0, 0.0, 1.0), (0.810225, 0.311365, 0.211593), (232, 151, 127)),
    ((0.5, 0.5, 0.707107), (2.1459, 0.8408, 0.5798), (255, 236, 200)),
    ((-0.6, -0.6, 0.529150), (0.04, 0.015, 0.01), (56, 33, 25)),
]
IDEAL_COVERAGE_1080P = 667_440
# SCENE.md "Expected agreement" (llvmpipe vs the ideal sphere, 640×480, icosphere(6)).
BOUND = {"mean": 0.005, "max": 1, "silhouette": 36}

# --------------------------------------------------------------------------------------------------- GLSL

VERTEX_SHADER = """
#version 330
uniform mat4 mvp;
in vec3 in_pos;
in vec3 in_nrm;
out vec3 v_pos;
out vec3 v_nrm;
void main() {
    v_pos = in_pos;              // model matrix = identity
    v_nrm = in_nrm;
    gl_Position = mvp * vec4(in_pos, 1.0);
}
"""

# SCENE.md's formula exactly (material 0), and Cook-Torrance GGX / height-correlated Smith / Schlick
# (material 1, as brdf-core's cook_torrance: f = kd/pi + ks D G F / (4 nl nv), 0 unless nl > 0 and nv > 0).
FRAGMENT_SHADER = """
#version 330
uniform vec3 eye;
uniform int material;
in vec3 v_pos;
in vec3 v_nrm;
out vec4 frag;
const vec3 kd = vec3(0.8, 0.3, 0.2);
const float PI = 3.14159265358979;
vec3 classic(vec3 N, vec3 L, vec3 V) {
    float nl = dot(N, L);
    vec3 H = normalize(L + V);
    vec3 c = kd * max(nl, 0.0);
    if (nl > 0.0) c += vec3(0.5) * pow(max(dot(N, H), 0.0), 32.0);
    return c;
}
float lambda_ggx(float c, float a2) {
    float c2 = c * c;
    return 0.5 * (-1.0 + sqrt(1.0 + a2 * (1.0 - c2) / c2));
}
vec3 cook_torrance(vec3 N, vec3 L, vec3 V) {
    float nl = dot(N, L);
    float nv = dot(N, V);
    if (nl <= 0.0 || nv <= 0.0) return vec3(0.0);
    vec3 H = normalize(L + V);
    float nh = max(dot(N, H), 0.0);
    float vh = max(dot(V, H), 0.0);
    float a2 = 0.09;
    float d = nh * nh * (a2 - 1.0) + 1.0;
    float D = a2 / (PI * d * d);
    float G = 1.0 / (1.0 + lambda_ggx(nl, a2) + lambda_ggx(nv, a2));
    float F = 0.04 + 0.96 * pow(1.0 - vh, 5.0);
    return (kd / PI + vec3(D * G * F / (4.0 * nl * nv))) * nl;
}
vec3 shade(vec3 N, vec3 L, vec3 V) {
    return material == 0 ? classic(N, L, V) : cook_torrance(N, L, V);
}
void main() {
    vec3 N = normalize(v_nrm);
    vec3 V = normalize(eye - v_pos);
    vec3 c = 0.05 * kd;
    c += vec3(1.0) * shade(N, normalize(vec3(1.0)), V);
    vec3 d = vec3(2.0) - v_pos;
    float r2 = dot(d, d);
    c += vec3(10.0 / r2) * shade(N, d / sqrt(r2), V);
    c = clamp(c, 0.0, 1.0);
    vec3 s = mix(12.92 * c, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, greaterThan(c, vec3(0.0031308)));
    frag = vec4(s, 1.0);
}
"""

# ------------------------------------------------------------------------------------------ llvmpipe worker


def _mesh_arrays(spec: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Vertex positions, normals and faces of ``icosphere:L`` or ``file:PATH`` as brdfpy builds them, placed
    as the benchmark places them (files: scaled into the unit sphere, so the same camera frames them)."""
    import brdfpy

    if spec.startswith("icosphere:"):
        m = brdfpy.icosphere(int(spec.split(":", 1)[1]))
        return m.vertices, m.normals, m.faces
    m = brdfpy.load_mesh(spec.split(":", 1)[1])
    if m.stats()["signed_volume"] < 0:
        m.flip_winding()
    c, r = m.bounding_sphere()
    xf = brdfpy.transforms.scale(1.0 / r) @ brdfpy.transforms.translate(-c)
    m = m.transformed(xf)
    return m.vertices, m.normals, m.faces


def _worker() -> int:
    """Serve llvmpipe renders over stdin/stdout (one JSON object per line), in a process whose environment
    fixes the driver and LP_NUM_THREADS."""
    import moderngl

    ctx = moderngl.create_standalone_context(backend="egl")
    info = {"renderer": ctx.info["GL_RENDERER"], "version": ctx.info["GL_VERSION"]}
    prog = ctx.program(vertex_shader=VERTEX_SHADER, fragment_shader=FRAGMENT_SHADER)
    vaos: dict[str, tuple[Any, ...]] = {}
    fbos: dict[tuple[int, int], Any] = {}
    print(json.dumps(info), flush=True)
    for line in sys.stdin:
        req = json.loads(line)
        w, h = req["width"], req["height"]
        if req["mesh"] not in vaos:
            v, n, f = _mesh_arrays(req["mesh"])
            vbo = ctx.buffer(np.hstack([v, n]).astype("f4").tobytes())
            ibo = ctx.buffer(f.astype("u4").tobytes())
            vaos[req["mesh"]] = (ctx.vertex_array(prog, [(vbo, "3f 3f", "in_pos", "in_nrm")], ibo), vbo, ibo)
        if (w, h) not in fbos:
            fbos[(w, h)] = ctx.framebuffer(
                color_attachments=[ctx.renderbuffer((w, h), 4)],
                depth_attachment=ctx.depth_renderbuffer((w, h)),
            )
        fbo, vao = fbos[(w, h)], vaos[req["mesh"]][0]
        proj = np.array(req["mvp"], dtype="f4")
        prog["mvp"].write(proj.T.copy().tobytes())  # GLSL matrices are column-major
        prog["eye"].value = (0.0, 0.0, 3.0)
        prog["material"].value = req["material"]
        fbo.use()
        ctx.enable(moderngl.DEPTH_TEST | moderngl.CULL_FACE)
        ctx.depth_func = "<"
        ctx.front_face = "ccw"

        def frame(read: bool, fbo: Any = fbo, vao: Any = vao) -> tuple[float, float]:
            t0 = time.perf_counter()
            fbo.clear(0.0, 0.0, 0.0, 0.0, depth=1.0)
            vao.render(moderngl.TRIANGLES)
            ctx.finish()
            t1 = time.perf_counter()
            if read:
                fbo.read(components=4)
            return t1 - t0, time.perf_counter() - t0

        out: dict[str, Any] = {}
        if req.get("image"):
            frame(False)
            raw = np.frombuffer(fbo.read(components=4), dtype=np.uint8).reshape(h, w, 4)[::-1]
            path = Path(req["image"])
            np.save(path, np.ascontiguousarray(raw))
            out["image"] = str(path)
        for _ in range(req.get("warmup", 0)):
            frame(True)
        times = [frame(True) for _ in range(req.get("frames", 0))]
        out["draw"] = [a for a, _ in times]
        out["frame"] = [b for _, b in times]
        print(json.dumps(out), flush=True)
    return 0


class Peer:
    """A running llvmpipe worker with ``LP_NUM_THREADS = threads``."""

    def __init__(self, threads: int) -> None:
        env = dict(os.environ, **GL_ENV, LP_NUM_THREADS=str(threads))
        self.proc = subprocess.Popen(
            [sys.executable, str(Path(__file__).resolve()), "--llvmpipe-worker"],
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            text=True,
            env=env,
        )
        self.info = self._read()

    def _read(self) -> dict[str, Any]:
        assert self.proc.stdout is not None
        line = self.proc.stdout.readline()
        if not line:
            raise RuntimeError("the llvmpipe worker exited (see its error above)")
        out: dict[str, Any] = json.loads(line)
        return out

    def ask(self, **req: Any) -> dict[str, Any]:
        assert self.proc.stdin is not None
        self.proc.stdin.write(json.dumps(req) + "\n")
        self.proc.stdin.flush()
        return self._read()

    def close(self) -> None:
        if self.proc.stdin:
            self.proc.stdin.close()
        self.proc.wait(timeout=30)
        if self.proc.stdout:
            self.proc.stdout.close()


def peers_available(install: bool) -> str | None:
    """``None`` when moderngl and Mesa's EGL are usable, else why not (after installing them if asked)."""
    missing = []
    try:
        out = subprocess.run(
            ["dpkg-query", "-W", "-f=${Status}\\n", *DEB_PACKAGES], capture_output=True, text=True
        )
        if out.stdout.count("install ok installed") < len(DEB_PACKAGES):
            missing.append("debian")
    except FileNotFoundError:
        missing.append("debian")
    try:
        import moderngl  # noqa: F401
    except ImportError:
        missing.append("moderngl")
    if missing and install:
        if "debian" in missing and shutil.which("apt-get"):
            subprocess.run(["apt-get", "update", "-qq"], check=False)
            subprocess.run(["apt-get", "install", "-y", "-qq", *DEB_PACKAGES], check=False)
        if "moderngl" in missing:
            subprocess.run([sys.executable, "-m", "pip", "install", "-q", "moderngl"], check=False)
        return peers_available(False)
    if "moderngl" in missing:
        return "moderngl is not installed (run with --install-peers to install it and Mesa's EGL packages)"
    probe = subprocess.run(
        [
            sys.executable,
            "-c",
            "import moderngl; print(moderngl.create_standalone_context(backend='egl').info['GL_RENDERER'])",
        ],
        capture_output=True,
        text=True,
        env=dict(os.environ, **GL_ENV),
    )
    if probe.returncode != 0 or "llvmpipe" not in probe.stdout:
        why = (probe.stderr.strip().splitlines() or ["?"])[-1]
        return f"no llvmpipe EGL context ({why}); Debian packages needed: {' '.join(DEB_PACKAGES)}"
    return None


# ------------------------------------------------------------------------------------------------- brdfpy


def _scene(mesh: str, material: int) -> tuple[Any, Any]:
    import brdfpy

    v, n, f = _mesh_arrays(mesh)
    model = (
        brdfpy.model("blinn_phong_classic", kd=KD, ks=0.5, shininess=32)
        if material == 0
        else brdfpy.model("cook_torrance", **CT_PARAMS)
    )
    scene = brdfpy.Scene(ambient_light=1.0, background=0.0)
    scene.add(brdfpy.Mesh(v, f, n), model, ambient=tuple(0.05 * c for c in KD))
    scene.add_light(brdfpy.DirectionalLight((-1, -1, -1), 1.0))
    scene.add_light(brdfpy.PointLight((2, 2, 2), 10.0, attenuation="inverse_square"))
    cam = brdfpy.Camera.perspective((0, 0, 3), (0, 0, 0), (0, 1, 0), 45.0, 0.1, 100.0)
    return scene, cam


def _brdfpy_frames(
    scene: Any, cam: Any, w: int, h: int, frames: int, warmup: int
) -> tuple[list[float], list[float]]:
    render, total = [], []
    for i in range(warmup + frames):
        t0 = time.perf_counter()
        img = scene.render(cam, w, h)
        t1 = time.perf_counter()
        _ = img.rgb
        t2 = time.perf_counter()
        if i >= warmup:
            render.append(t1 - t0)
            total.append(t2 - t0)
    return render, total


def _ms(xs: list[float]) -> float:
    return 1000.0 * statistics.median(xs)


def _load() -> float:
    """The 1-minute load average (the 2 cores are shared: a figure taken at a high load is suspect)."""
    return os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")


#: Issue 8's target: brdfpy's full frame at most this fraction of llvmpipe's draw + read-back.
TARGET = 0.8


def default_scene(threads: list[int], frames: int) -> list[dict[str, Any]]:
    """The scene ``brdfpy render --ao`` draws, with its defaults (1280×720, 4 samples, shadows, ACES,
    per-vertex obscurance): the first frame, which builds the BVH and estimates the obscurance, and the
    median of the next ``frames`` with the camera moving (a turntable: the geometry is unchanged, so both
    are reused)."""
    import brdfpy
    from brdfpy import render_cmd

    parser = argparse.ArgumentParser()
    render_cmd.add_parser(parser.add_subparsers())
    args = parser.parse_args(["render", "--ao"])
    w, h = 1280, 720
    args.width, args.height = w, h  # what `brdfpy render` sets before building the scene
    rows = []
    for t in threads:
        brdfpy.set_num_threads(t)
        scene, cam = render_cmd.build_scene(args)
        times = []
        for i in range(frames + 1):
            angle = 0.05 * i
            eye = np.asarray(cam.eye, dtype=np.float64)
            rot = np.array([[np.cos(angle), 0, np.sin(angle)], [0, 1, 0], [-np.sin(angle), 0, np.cos(angle)]])
            c = brdfpy.Camera.perspective(tuple(rot @ eye), cam.target, cam.up, cam.fovy, cam.near, cam.far)
            t0 = time.perf_counter()
            img = scene.render(c, w, h, samples=4, tonemap="aces", ao=True, shadows=True)
            _ = img.rgb
            times.append(time.perf_counter() - t0)
        faces = sum(i.mesh.n_faces for i in scene.instances)
        row = {
            "scene": "brdfpy render --ao",
            "triangles": faces,
            "size": [w, h],
            "samples": 4,
            "threads": t,
            "first_frame_ms": 1000 * times[0],
            "frame_ms": _ms(times[1:]),
            "loadavg": _load(),
        }
        rows.append(row)
        print(
            f"default scene ({faces:,} triangles, {w}x{h}, 4 spp, shadows + obscurance), {t} thread(s): "
            f"first frame {row['first_frame_ms']:.0f} ms (BVH + obscurance), then {row['frame_ms']:.0f} ms "
            f"per frame (turntable; load {row['loadavg']:.2f})"
        )
    brdfpy.set_num_threads(None)
    return rows


# --------------------------------------------------------------------------------------------------- checks


def check_values(w: int, h: int) -> dict[str, Any]:
    """SCENE.md's check values: the illumination model at the three points (through ``Model.shade``) and the
    rendered pixels whose normal is nearest to them, plus coverage at 1080p for levels 5–8."""
    import brdfpy

    out: dict[str, Any] = {"points": []}
    model = brdfpy.model("blinn_phong_classic", kd=KD, ks=0.5, shininess=32)
    scene, cam = _scene("icosphere:8", 0)
    img = scene.render(cam, w, h, outputs=("rgb", "normal", "depth"))
    normals = img.normal.reshape(-1, 3)
    for p, linear, rgb8 in CHECKS:
        pp = np.array(p)
        c = 0.05 * np.array(KD)
        v = np.array([0.0, 0.0, 3.0]) - pp
        c += model.shade((1, 1, 1), v, pp).astype(np.float64)
        d = np.array([2.0, 2.0, 2.0]) - pp
        c += 10.0 / d.dot(d) * model.shade(d, v, pp).astype(np.float64)
        k = int(np.argmin(((normals - pp) ** 2).sum(axis=1)))
        got = img.rgb.reshape(-1, 3)[k].tolist()
        out["points"].append(
            {
                "P": p,
                "linear": [round(float(x), 6) for x in c],
                "linear_expected": linear,
                "linear_ok": bool(np.allclose(c, linear, atol=1e-4)),
                "pixel": got,
                "pixel_expected": rgb8,
                "pixel_ok": bool(max(abs(a - b) for a, b in zip(got, rgb8)) <= 1),
            }
        )
    out["centre_pixel"] = img.rgb[h // 2, w // 2].tolist()
    out["coverage_level8"] = img.covered_pixels
    out["coverage_ideal"] = IDEAL_COVERAGE_1080P if (w, h) == (1920, 1080) else None
    return out


def _oracle() -> Any:
    sys.path.insert(0, str(ROOT / "tests"))
    try:
        import raster_oracle
    except ImportError:
        return None
    return raster_oracle


def agreement(peer: Peer | None, w: int = 640, h: int = 480, level: int = 6) -> dict[str, Any]:
    """brdfpy vs llvmpipe and vs the ray-cast ideal sphere (SCENE.md "Expected agreement")."""
    scene, cam = _scene(f"icosphere:{level}", 0)
    img = scene.render(cam, w, h)
    ours, our_mask = img.rgb.astype(np.int32), img.mask
    out: dict[str, Any] = {"size": [w, h], "level": level, "bound": BOUND}

    def compare(rgb: np.ndarray, mask: np.ndarray) -> dict[str, Any]:
        both = mask & our_mask
        d = np.abs(ours - rgb.astype(np.int32))[both]
        res = {
            "mean": float(d.mean()),
            "max": int(d.max()),
            "silhouette": int((mask ^ our_mask).sum()),
            "pixels": int(both.sum()),
        }
        res["within_bound"] = (
            res["mean"] <= BOUND["mean"]
            and res["max"] <= BOUND["max"]
            and res["silhouette"] <= BOUND["silhouette"]
        )
        return res

    if peer is not None:
        with tempfile.TemporaryDirectory() as tmp:
            mvp = (cam.projection_matrix(w / h) @ cam.view_matrix()).tolist()
            r = peer.ask(
                mesh=f"icosphere:{level}",
                material=0,
                width=w,
                height=h,
                mvp=mvp,
                image=str(Path(tmp) / "gl.npy"),
            )
            gl = np.load(r["image"])
        out["vs_llvmpipe"] = compare(gl[..., :3], gl[..., 3] > 0)
    oracle = _oracle()
    if oracle is not None:
        import oracle as brdf_oracle  # tests/oracle: the BRDF oracle, for the 8-bit conversion

        sc = oracle.scene
        lin, mask = oracle.raycast.sphere(sc.camera(), w, h, sc.material(), sc.lights())
        out["vs_ideal_sphere"] = compare(brdf_oracle.tonemap.to_uint8(lin, "clamp"), mask)
    return out


# ------------------------------------------------------------------------------------------------------ main


def main(argv: list[str] | None = None) -> dict[str, Any]:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0] if __doc__ else None)
    p.add_argument(
        "--quick", action="store_true", help="level 5 only, 3 frames, 480×270: checks that it runs"
    )
    p.add_argument("--install-peers", action="store_true", help="install moderngl and Mesa's EGL if missing")
    p.add_argument("--no-peer", action="store_true", help="skip llvmpipe")
    p.add_argument("--frames", type=int, default=10, help="timed frames per configuration (default 10)")
    p.add_argument("--warmup", type=int, default=None, help="untimed frames first (default 3; llvmpipe 30)")
    p.add_argument("--levels", default="5,7,8", help="icosphere levels (default 5,7,8)")
    p.add_argument("--threads", default="2", help="thread counts (default 2; e.g. 1,2)")
    p.add_argument(
        "--materials",
        default="blinn_phong_classic,cook_torrance",
        help="materials timed (default blinn_phong_classic,cook_torrance)",
    )
    p.add_argument("--no-default-scene", action="store_true", help="skip the default brdfpy render scene")
    p.add_argument("--size", default="1920x1080", help="image size (default 1920x1080)")
    p.add_argument("--mesh", default=str(ASSETS / "stanford_bunny_70k.ply"), help="the real mesh to time")
    p.add_argument("--llvmpipe-worker", action="store_true", help=argparse.SUPPRESS)
    args = p.parse_args(argv)
    if args.llvmpipe_worker:
        raise SystemExit(_worker())
    import brdfpy

    w, h = (int(x) for x in args.size.lower().split("x"))
    levels = [int(x) for x in args.levels.split(",")]
    threads = [int(x) for x in args.threads.split(",")]
    frames = args.frames
    if args.quick:
        w, h, levels, frames = 480, 270, [5], 3
    warm = 3 if args.warmup is None else args.warmup
    warm_gl = 30 if args.warmup is None else args.warmup
    if args.quick:
        warm = warm_gl = 1

    result: dict[str, Any] = {
        "benchmark": "render",
        "machine": {
            "cpus": os.cpu_count(),
            "platform": platform.platform(),
            "python": platform.python_version(),
            # The 2 cores are often shared: a load well above 0 at either end makes the figures suspect.
            "loadavg_before": os.getloadavg()[0] if hasattr(os, "getloadavg") else None,
        },
        "size": [w, h],
        "frames": frames,
        "rows": [],
    }
    why = "--no-peer" if args.no_peer else peers_available(args.install_peers)
    peers: dict[int, Peer] = {}
    if why is None:
        peers = {t: Peer(t) for t in threads}
        result["llvmpipe"] = next(iter(peers.values())).info
        print(f"peer: {result['llvmpipe']['renderer']} ({result['llvmpipe']['version']})")
    else:
        print(f"llvmpipe skipped: {why}")
        result["llvmpipe_skipped"] = why

    meshes = [(f"icosphere:{lv}", f"icosphere({lv})") for lv in levels]
    if not args.quick:
        if Path(args.mesh).exists():
            meshes.append((f"file:{args.mesh}", Path(args.mesh).stem))
        else:
            print(f"real mesh skipped: {args.mesh} not found")
    mats = [
        m for m in [(0, "blinn_phong_classic"), (1, "cook_torrance")] if m[1] in args.materials.split(",")
    ]
    warmed: dict[int, bool] = {}
    header = (
        f"{'mesh':<22}{'tris':>10} {'material':<20}{'thr':>4}{'render':>8}{'frame':>8}"
        f"{'llvmpipe':>10}{'draw':>7}{'ours/gl':>9}  load"
    )
    print(header)
    try:
        for mesh, label in meshes:
            for mat, mat_name in mats:
                scene, cam = _scene(mesh, mat)
                tris = scene.instances[0].mesh.n_faces
                mvp = (cam.projection_matrix(w / h) @ cam.view_matrix()).tolist()
                for t in threads:
                    brdfpy.set_num_threads(t)
                    # Interleave: half of the frames each, twice, so drift hits both alike.
                    ours_r: list[float] = []
                    ours_t: list[float] = []
                    gl_f: list[float] = []
                    gl_d: list[float] = []
                    for half in range(2):
                        n = frames // 2 if half == 0 else frames - frames // 2
                        r, tt = _brdfpy_frames(scene, cam, w, h, n, warm if half == 0 else 1)
                        ours_r += r
                        ours_t += tt
                        if t in peers:
                            g = peers[t].ask(
                                mesh=mesh,
                                material=mat,
                                width=w,
                                height=h,
                                mvp=mvp,
                                frames=n,
                                warmup=(warm_gl if not warmed.get(t) else 5) if half == 0 else 2,
                            )
                            warmed[t] = True  # llvmpipe's JIT warms up once per process (~30 frames)
                            gl_f += g["frame"]
                            gl_d += g["draw"]
                    row: dict[str, Any] = {
                        "mesh": label,
                        "triangles": tris,
                        "material": mat_name,
                        "threads": t,
                        "brdfpy_render_ms": _ms(ours_r),
                        "brdfpy_frame_ms": _ms(ours_t),
                        "loadavg": _load(),
                    }
                    if gl_f:
                        row["llvmpipe_frame_ms"] = _ms(gl_f)
                        row["llvmpipe_draw_ms"] = _ms(gl_d)
                        row["ratio_llvmpipe_over_brdfpy"] = row["llvmpipe_frame_ms"] / row["brdfpy_frame_ms"]
                        row["ratio_brdfpy_over_llvmpipe"] = row["brdfpy_frame_ms"] / row["llvmpipe_frame_ms"]
                        row["target_met"] = row["ratio_brdfpy_over_llvmpipe"] <= TARGET
                    result["rows"].append(row)
                    gl = (
                        f"{row['llvmpipe_frame_ms']:10.1f}{row['llvmpipe_draw_ms']:7.1f}"
                        f"{row['ratio_brdfpy_over_llvmpipe']:8.2f}{' ' if row['target_met'] else '!'}"
                        if gl_f
                        else f"{'-':>10}{'-':>7}{'-':>9}"
                    )
                    print(
                        f"{label:<22}{tris:>10,} {mat_name:<20}{t:>4}{row['brdfpy_render_ms']:8.1f}"
                        f"{row['brdfpy_frame_ms']:8.1f}{gl} {row['loadavg']:5.2f}",
                        flush=True,
                    )
        if gl_rows := [r for r in result["rows"] if "target_met" in r]:
            met = sum(r["target_met"] for r in gl_rows)
            print(f"target frame <= {TARGET} x llvmpipe ('!' = missed): met in {met} of {len(gl_rows)} rows")
        if not args.no_default_scene and not args.quick:
            result["default_scene"] = default_scene(threads, frames)
        # Thread scaling: 1-thread time over 2-thread time, per (mesh, material).
        scaling = []
        for r1 in result["rows"]:
            for r2 in result["rows"]:
                if (r1["mesh"], r1["material"], r1["threads"], r2["threads"]) == (
                    r2["mesh"],
                    r2["material"],
                    1,
                    2,
                ):
                    s = {
                        "mesh": r1["mesh"],
                        "material": r1["material"],
                        "brdfpy": r1["brdfpy_frame_ms"] / r2["brdfpy_frame_ms"],
                    }
                    if "llvmpipe_frame_ms" in r1 and "llvmpipe_frame_ms" in r2:
                        s["llvmpipe"] = r1["llvmpipe_frame_ms"] / r2["llvmpipe_frame_ms"]
                    scaling.append(s)
        result["speedup_2_threads"] = scaling
        for s in scaling:
            gl = f", llvmpipe {s['llvmpipe']:.2f}x" if "llvmpipe" in s else ""
            print(f"2-thread speed-up {s['mesh']} {s['material']}: brdfpy {s['brdfpy']:.2f}x{gl}")

        brdfpy.set_num_threads(None)
        result["checks"] = check_values(1920, 1080) if not args.quick else check_values(w, h)
        for pt in result["checks"]["points"]:
            print(
                f"check P={pt['P']}: linear {pt['linear']} (SCENE.md {pt['linear_expected']}) "
                f"{'ok' if pt['linear_ok'] else 'MISMATCH'}; pixel {pt['pixel']} "
                f"(SCENE.md {pt['pixel_expected']}) "
                f"{'ok' if pt['pixel_ok'] else 'MISMATCH'}"
            )
        ch = result["checks"]
        print(
            f"centre pixel {ch['centre_pixel']}; icosphere(8) covers {ch['coverage_level8']:,} pixels"
            + (f" (ideal sphere {ch['coverage_ideal']:,})" if ch["coverage_ideal"] else "")
        )
        peer = peers.get(2) or next(iter(peers.values()), None)
        agr = agreement(peer)
        result["agreement"] = agr
        for key in ("vs_llvmpipe", "vs_ideal_sphere"):
            if key in agr:
                a = agr[key]
                print(
                    f"agreement {key} (640x480, icosphere(6)): mean {a['mean']:.4f}, max {a['max']} levels "
                    f"inside ({a['pixels']:,} px), silhouette {a['silhouette']} px — bound mean "
                    f"{BOUND['mean']}, max {BOUND['max']}, silhouette {BOUND['silhouette']}: "
                    f"{'within' if a['within_bound'] else 'OUTSIDE'}"
                )
        result["oracle"] = oracle_baseline(args.quick)
    finally:
        for peer_ in peers.values():
            peer_.close()
    return result


def oracle_baseline(quick: bool) -> dict[str, Any] | None:
    """The NumPy reference rasterizer on icosphere(5) at 160×90, per pixel scaled to 1080p (it is linear in
    pixels only roughly: its cost is mostly per triangle)."""
    oracle = _oracle()
    if oracle is None:
        print("NumPy reference rasterizer skipped: tests/raster_oracle not found")
        return None
    import brdfpy

    sc = oracle.scene
    w, h, level = (80, 45, 3) if quick else (160, 90, 5)
    v, f = oracle.geometry.icosphere(level)
    inst = oracle.raster.Instance(v, f, sc.material(), normals=v)
    scene = oracle.raster.Scene([inst], sc.lights(), 1.0, 0.0)
    t0 = time.perf_counter()
    oracle.raster.render(scene, sc.camera(), w, h, "phong")
    t_oracle = time.perf_counter() - t0
    ours, cam = _scene(f"icosphere:{level}", 0)
    brdfpy.set_num_threads(1)
    r, _ = _brdfpy_frames(ours, cam, w, h, 5, 2)
    brdfpy.set_num_threads(None)
    out = {"size": [w, h], "level": level, "oracle_ms": 1000 * t_oracle, "brdfpy_1thread_ms": _ms(r)}
    out["ratio_oracle_over_brdfpy"] = out["oracle_ms"] / out["brdfpy_1thread_ms"]
    print(
        f"NumPy reference rasterizer, icosphere({level}) at {w}x{h}: {out['oracle_ms']:.0f} ms vs brdfpy "
        f"(1 thread) "
        f"{out['brdfpy_1thread_ms']:.2f} ms: {out['ratio_oracle_over_brdfpy']:.0f}x"
    )
    return out


if __name__ == "__main__":
    if "--llvmpipe-worker" in sys.argv:
        raise SystemExit(_worker())
    res = main(sys.argv[1:])
    if hasattr(os, "getloadavg"):
        res["machine"]["loadavg_after"] = os.getloadavg()[0]
        m = res["machine"]
        print(f"load average: {m['loadavg_before']:.2f} before, {m['loadavg_after']:.2f} after")
    out_dir = HERE / "results"
    out_dir.mkdir(exist_ok=True)
    (out_dir / "render.json").write_text(json.dumps(res, indent=2) + "\n")
    print(f"wrote {out_dir / 'render.json'}")
