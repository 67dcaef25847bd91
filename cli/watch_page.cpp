// The page snell watch serves: the newest image, refreshed as passes finish; the
// diagnostics and statistics beside it; the linear value of the pixel under the
// cursor. It polls /state four times a second (one small JSON answer from
// localhost) rather than holding a stream open, so a page left open across a
// restart of snell watch picks up again by itself.
#include "cli/watch_http.hpp"

namespace snell::cli {

const char* watch_page_html() {
  return R"HTML(<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<title>snell watch</title>
<style>
  body { margin: 0; font: 14px/1.4 system-ui, sans-serif; background: #1e1f22; color: #ddd; }
  header { padding: 8px 14px; background: #2b2d31; display: flex; gap: 16px; align-items: baseline; }
  header b { color: #fff; }
  #status { color: #9ab; }
  #status.errors { color: #f87; }
  main { display: flex; gap: 14px; padding: 14px; align-items: flex-start; }
  #view { flex: 0 1 auto; min-width: 0; }
  #image { display: block; max-width: 100%; image-rendering: pixelated; background: #000;
           cursor: crosshair; }
  #image.stale { opacity: 0.45; }
  #pixel { font-family: ui-monospace, monospace; margin-top: 6px; color: #cde; }
  aside { flex: 1 1 360px; min-width: 300px; overflow: hidden; }
  h2 { font-size: 13px; text-transform: uppercase; letter-spacing: 0.05em; color: #889;
       margin: 0 0 4px 0; }
  pre { margin: 0 0 14px 0; padding: 8px; background: #2b2d31; border-radius: 4px;
        font: 12px/1.35 ui-monospace, monospace; white-space: pre; overflow-x: auto; }
  #stats { white-space: pre-wrap; }  /* diagnostics stay unwrapped: their carets line up */
  #diagnostics.errors { color: #fbb; border-left: 3px solid #e55; }
  #diagnostics.clean { color: #9c9; }
</style>
</head>
<body>
<header><b>snell watch</b> <span id="scene"></span> <span id="status">connecting…</span></header>
<main>
  <div id="view">
    <img id="image" alt="the newest pass">
    <div id="pixel">pixel: –</div>
  </div>
  <aside>
    <h2>Diagnostics</h2>
    <pre id="diagnostics" class="clean">none</pre>
    <h2>Statistics</h2>
    <pre id="stats">–</pre>
  </aside>
</main>
<script>
"use strict";
const img = document.getElementById("image");
const pixel = document.getElementById("pixel");
let shown = -1;           // the image revision on screen
let cursor = null;        // the pixel under the cursor, or null: the centre is shown
let width = 0, height = 0;

function fmt(v) { return v === null ? "NaN/inf" : v.toPrecision(5); }

async function showPixel() {
  if (!width || !height) return;
  const p = cursor || { x: Math.floor(width / 2), y: Math.floor(height / 2) };
  try {
    const r = await fetch(`/pixel?x=${p.x}&y=${p.y}`, { cache: "no-store" });
    const j = await r.json();
    if (j.rgb)
      pixel.textContent = `pixel ${j.x},${j.y}${cursor ? "" : " (centre)"}: linear RGB ` +
        `${fmt(j.rgb[0])} ${fmt(j.rgb[1])} ${fmt(j.rgb[2])} (${j.spp ? j.spp + " spp" : "preview"})`;
  } catch (e) { /* the next poll tries again */ }
}

img.addEventListener("load", () => {
  img.dataset.loaded = `${shown} ${img.naturalWidth}x${img.naturalHeight}`;
  showPixel();
});
img.addEventListener("mousemove", (e) => {
  if (!img.naturalWidth) return;
  const x = Math.floor(e.offsetX * img.naturalWidth / img.clientWidth);
  const y = Math.floor(e.offsetY * img.naturalHeight / img.clientHeight);
  cursor = { x: Math.min(Math.max(x, 0), img.naturalWidth - 1),
             y: Math.min(Math.max(y, 0), img.naturalHeight - 1) };
  showPixel();
});
img.addEventListener("mouseleave", () => { cursor = null; showPixel(); });

async function poll() {
  try {
    const r = await fetch("/state", { cache: "no-store" });
    const s = await r.json();
    document.getElementById("scene").textContent = s.scene;
    const st = document.getElementById("status");
    st.textContent = s.status;
    st.className = s.errors ? "errors" : "";
    const d = document.getElementById("diagnostics");
    d.textContent = s.diagnostics || "none";
    d.className = s.errors ? "errors" : "clean";
    document.getElementById("stats").textContent = s.stats || "–";
    img.classList.toggle("stale", s.errors);
    width = s.width; height = s.height;
    if (s.image_revision > 0 && s.image_revision !== shown) {
      shown = s.image_revision;
      img.src = `/image.png?rev=${shown}`;
    }
  } catch (e) {
    document.getElementById("status").textContent = "snell watch is not answering";
  }
  setTimeout(poll, 250);
}
poll();
</script>
</body>
</html>
)HTML";
}

}  // namespace snell::cli
