// Helpers the deploy tests and benches share.
import net from 'node:net';

// A TCP port free on 127.0.0.1 now (the system's pick).
export function freePort() {
  return new Promise((resolve, reject) => {
    const s = net.createServer();
    s.on('error', reject);
    s.listen(0, '127.0.0.1', () => {
      const { port } = s.address();
      s.close(() => resolve(port));
    });
  });
}

// The camera `angle` radians around the default camera's target, about the scene's up.
export function orbit(camera, up, angle) {
  const t = camera.target;
  const v = camera.position.map((x, i) => x - t[i]);
  const n = Math.hypot(...up);
  const k = up.map((x) => x / n);
  const c = Math.cos(angle);
  const s = Math.sin(angle);
  const dot = k[0] * v[0] + k[1] * v[1] + k[2] * v[2];
  const cross = [k[1] * v[2] - k[2] * v[1], k[2] * v[0] - k[0] * v[2], k[0] * v[1] - k[1] * v[0]];
  const r = v.map((x, i) => x * c + cross[i] * s + k[i] * dot * (1 - c));
  return {
    position: r.map((x, i) => x + t[i]),
    target: t,
    up: camera.up || up,
    fov: camera.fov || 50,
  };
}
