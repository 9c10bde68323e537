#!/usr/bin/env python3
"""What drawing N disks costs the browser's WebGL 2, by form: instanced quads,
instanced points, and points of one vertex each (the page's form,
web/page.js). A probe page of its own: N random disks of radius 1 at packing
0.5 on a 737 x 737 canvas, each draw followed by a 1-pixel read back; prints
the median of FRAMES draws. In headless Chromium here WebGL 2 runs in
software (SwiftShader).
  usage: .venv/bin/python bench/webgl_draw.py [--sizes 1000 10000 100000] [--frames 7]"""
import argparse
import pathlib
import sys
import tempfile

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1] / "tests" / "web"))
from browser import open_chromium, serve  # noqa: E402

PROBE = """<!doctype html><link rel="icon" href="data:,"><canvas id="c" width="737" height="737"></canvas><script>
const gl = document.getElementById('c').getContext('webgl2', {preserveDrawingBuffer: true, antialias: false});
function program(vertex, fragment) {
  const p = gl.createProgram();
  for (const [type, source] of [[gl.VERTEX_SHADER, vertex], [gl.FRAGMENT_SHADER, fragment]]) {
    const s = gl.createShader(type); gl.shaderSource(s, '#version 300 es\\n' + source); gl.compileShader(s);
    gl.attachShader(p, s);
  }
  gl.linkProgram(p);
  return p;
}
const quads = program(`layout(location = 0) in vec2 p; uniform float k; out vec2 l;
  void main() { l = vec2(gl_VertexID & 1, gl_VertexID >> 1) * 2.0 - 1.0; gl_Position = vec4((p + l) * k - 1.0, 0, 1); }`,
  `precision highp float; in vec2 l; out vec4 f; void main() { if (dot(l, l) > 1.0) discard; f = vec4(1); }`);
const points = program(`layout(location = 0) in vec2 p; uniform float k;
  void main() { gl_Position = vec4(p * k - 1.0, 0, 1); gl_PointSize = 737.0 * k; }`,
  `precision highp float; out vec4 f; void main() { vec2 l = gl_PointCoord * 2.0 - 1.0; if (dot(l, l) > 1.0) discard; f = vec4(1); }`);
gl.bindBuffer(gl.ARRAY_BUFFER, gl.createBuffer());
gl.enableVertexAttribArray(0);
gl.vertexAttribPointer(0, 2, gl.FLOAT, false, 24, 0);  // the engine's 24-byte disks
window.draw = (n, form, frames) => {
  const side = Math.sqrt(n * Math.PI / 0.5), disks = new Float32Array(6 * n);
  for (let i = 0; i < n; i++) { disks[6 * i] = Math.random() * side; disks[6 * i + 1] = Math.random() * side; }
  gl.bufferData(gl.ARRAY_BUFFER, disks, gl.STATIC_DRAW);
  gl.vertexAttribDivisor(0, form === 'points' ? 0 : 1);
  const p = form === 'quads' ? quads : points;
  gl.useProgram(p);
  gl.uniform1f(gl.getUniformLocation(p, 'k'), 2 / side);
  const times = [];
  for (let f = 0; f < frames; f++) {
    const t0 = performance.now();
    gl.clear(gl.COLOR_BUFFER_BIT);
    if (form === 'quads') gl.drawArraysInstanced(gl.TRIANGLE_STRIP, 0, 4, n);
    else if (form === 'instanced points') gl.drawArraysInstanced(gl.POINTS, 0, 1, n);
    else gl.drawArrays(gl.POINTS, 0, n);
    gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, new Uint8Array(4));
    times.push(performance.now() - t0);
  }
  return times.sort((a, b) => a - b)[frames >> 1];
};
</script>"""


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[1000, 10000, 100000])
    parser.add_argument("--frames", type=int, default=7)
    args = parser.parse_args()
    browser = open_chromium()
    try:
        with tempfile.TemporaryDirectory() as folder:
            (pathlib.Path(folder) / "index.html").write_text(PROBE)
            with serve(folder) as url:
                browser.get(url)
                for form in ("quads", "instanced points", "points"):
                    for n in args.sizes:
                        ms = browser.execute_script("return draw(arguments[0], arguments[1], arguments[2])",
                                                    n, form, args.frames)
                        print(f"{form} N={n}: {ms:.1f} ms a draw (median of {args.frames})")
    finally:
        browser.quit()


if __name__ == "__main__":
    main()
