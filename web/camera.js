// An orbit camera around a target, in the scene's world units and with the scene's up axis:
// drag orbits, right/shift-drag pans, the wheel zooms, and WASD/QE walk target and eye together.
// The API wants {position, target, up, fov}; this keeps (target, distance, yaw, pitch) instead so
// that orbiting never rolls the view and the eye cannot pass through the target.

const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
const add = (a, b) => [a[0] + b[0], a[1] + b[1], a[2] + b[2]];
const scale = (a, s) => [a[0] * s, a[1] * s, a[2] * s];
const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
const length = (a) => Math.hypot(a[0], a[1], a[2]);
const normalize = (a) => scale(a, 1 / (length(a) || 1));

const MAX_PITCH = 1.55; // just short of straight down/up, where yaw would be undefined

export class OrbitCamera {
  // scene: an entry of GET /api/scenes (bounds, up, defaultCamera); defaultCamera: where R goes
  // back to, when not the store's (a session's, which a scene file's camera sets).
  constructor(scene, defaultCamera = scene.defaultCamera) {
    this.up = normalize(scene.up || [0, 0, 1]);
    // Two axes spanning the ground plane, for yaw.
    const ref = Math.abs(this.up[0]) < 0.9 ? [1, 0, 0] : [0, 1, 0];
    this.e2 = normalize(cross(this.up, ref));
    this.e1 = cross(this.e2, this.up);
    const b = scene.bounds || { min: [-1, -1, -1], max: [1, 1, 1] };
    this.sceneSize = length(sub(b.max, b.min)) || 1;
    this.defaultCamera = defaultCamera || {
      position: add(b.max, scale(sub(b.max, b.min), 0.5)),
      target: scale(add(b.min, b.max), 0.5),
    };
    this.reset();
  }

  // Back to the scene's default camera.
  reset() {
    const c = this.defaultCamera;
    this.fov = c.fov || 50;
    this.target = [...c.target];
    const d = sub(c.position, c.target);
    this.distance = Math.max(length(d), this.minDistance());
    this.pitch = Math.asin(Math.max(-1, Math.min(1, dot(d, this.up) / (length(d) || 1))));
    this.yaw = Math.atan2(dot(d, this.e2), dot(d, this.e1));
  }

  minDistance() {
    return this.sceneSize * 1e-4;
  }

  position() {
    const cp = Math.cos(this.pitch);
    const dir = add(
      add(scale(this.e1, cp * Math.cos(this.yaw)), scale(this.e2, cp * Math.sin(this.yaw))),
      scale(this.up, Math.sin(this.pitch)),
    );
    return add(this.target, scale(dir, this.distance));
  }

  // View axes: forward (eye to target), right, and the camera's own up.
  axes() {
    const forward = normalize(sub(this.target, this.position()));
    const right = normalize(cross(forward, this.up));
    return { forward, right, up: cross(right, forward) };
  }

  // The camera object of the API.
  toApi() {
    return { position: this.position(), target: [...this.target], up: [...this.up], fov: this.fov };
  }

  // Drag by (dx, dy) pixels: turn around the target.
  orbit(dx, dy) {
    this.yaw -= dx * 0.006;
    this.pitch = Math.max(-MAX_PITCH, Math.min(MAX_PITCH, this.pitch + dy * 0.006));
  }

  // Right-drag by (dx, dy) pixels in a view heightPx tall: the point under the mouse stays there.
  pan(dx, dy, heightPx) {
    const perPixel = (2 * this.distance * Math.tan((this.fov * Math.PI) / 360)) / Math.max(heightPx, 1);
    const { right, up } = this.axes();
    this.target = add(this.target, add(scale(right, -dx * perPixel), scale(up, dy * perPixel)));
  }

  // Wheel: positive steps move away; the distance changes by a fixed factor per step.
  zoom(steps) {
    const d = this.distance * Math.exp(steps * 0.15);
    this.distance = Math.max(this.minDistance(), Math.min(this.sceneSize * 10, d));
  }

  // Walk: forward/right along the ground plane, up along the scene's up, in world units.
  walk(forward, right, up) {
    const f = this.axes().forward;
    let ground = sub(f, scale(this.up, dot(f, this.up)));
    // Looking straight down: walk the way the top of the view points.
    if (length(ground) < 1e-6) ground = this.axes().up;
    ground = normalize(ground);
    const side = normalize(cross(ground, this.up));
    this.target = add(this.target, add(add(scale(ground, forward), scale(side, right)), scale(this.up, up)));
  }

  // Walking speed in world units per second: half the orbit distance, kept between 2% and 10% of
  // the scene's size, so that a close view walks slowly and an overview crosses the scene quickly.
  walkSpeed() {
    return Math.max(this.sceneSize * 0.02, Math.min(this.sceneSize * 0.1, this.distance * 0.5));
  }
}
