// Render mode (?render=1&item=ID&fps=25&from=0&to=10&width=960&height=540): frame by frame, not by the wall
// clock; each frame drawn with the "follow" camera, composited with a small time label, posted as PNG to
// POST /api/render/frame?index=K (each answer awaited), then POST /api/render/done.
import { post } from './api.js';
import { showError, floorIndex } from './util.js';

function num(params, name, fallback) {
  const v = Number(params.get(name));
  return params.has(name) && Number.isFinite(v) ? v : fallback;
}

function toPng(canvas) {
  return new Promise((resolve, reject) => canvas.toBlob((b) => (b ? resolve(b) : reject(new Error('canvas.toBlob gave nothing'))), 'image/png'));
}

/** deps: {world, rec, params, seekFrame(frame), state} */
export async function runRender({ world, rec, params, seekFrame, state }) {
  if (!rec) { showError('render: the item is not a recording'); return; }
  const fps = Math.max(0.1, Math.min(240, num(params, 'fps', 25)));
  const from = Math.max(rec.times[0], num(params, 'from', rec.times[0]));
  const to = Math.min(rec.times[rec.frames - 1], num(params, 'to', rec.times[rec.frames - 1]));
  const [w, h] = world.fixedSize;
  const out = document.createElement('canvas');
  out.width = w;
  out.height = h;
  const g = out.getContext('2d');
  const count = Math.max(1, Math.floor((to - from) * fps + 1e-6) + 1);
  world.setPreset('follow', 1.9);  // closer than the page's default: the robot fills a still or a clip
  try {
    for (let k = 0; k < count; k++) {
      const t = from + k / fps;
      seekFrame(floorIndex(rec.times, t + 1e-9));
      world.follow();
      world.render();
      g.drawImage(world.canvas, 0, 0, w, h);
      const label = `t = ${state.time.toFixed(2)} s`;
      const size = Math.max(11, Math.round(h / 36));
      g.font = `${size}px ui-monospace, "DejaVu Sans Mono", monospace`;
      const tw = g.measureText(label).width;
      g.fillStyle = 'rgba(0, 0, 0, 0.45)';
      g.fillRect(8, 8, tw + 12, size + 10);
      g.fillStyle = '#e8ecf1';
      g.textBaseline = 'top';
      g.fillText(label, 14, 13);
      const png = await toPng(out);
      await post(`/api/render/frame?index=${k}`, png, { raw: true });
    }
    await post('/api/render/done');
  } catch (err) {
    showError(err);
  }
}
