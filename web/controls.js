// Mouse and keyboard on the frame view, turned into OrbitCamera moves. Calls onChange() after
// every move; the viewer decides what to request.
//   drag: orbit · right-drag, shift-drag or middle-drag: pan · wheel: zoom
//   W/S or Up/Down: forward/back · A/D or Left/Right: sideways · E/Q: up/down · Shift: faster
//   R: back to the scene's default camera

const WALK_KEYS = {
  KeyW: [1, 0, 0], ArrowUp: [1, 0, 0],
  KeyS: [-1, 0, 0], ArrowDown: [-1, 0, 0],
  KeyD: [0, 1, 0], ArrowRight: [0, 1, 0],
  KeyA: [0, -1, 0], ArrowLeft: [0, -1, 0],
  KeyE: [0, 0, 1],
  KeyQ: [0, 0, -1],
};

export class ViewControls {
  // element: the focusable view; getCamera(): the current OrbitCamera (it changes with the scene).
  constructor(element, getCamera, onChange) {
    this.element = element;
    this.getCamera = getCamera;
    this.onChange = onChange;
    this.drag = null; // {mode: 'orbit'|'pan', x, y, pointerId}
    this.keys = new Set();
    this.lastTick = 0;
    this.ticking = false; // one animation-frame loop at most
    this.fast = false;

    element.addEventListener('pointerdown', (e) => this.pointerDown(e));
    element.addEventListener('pointermove', (e) => this.pointerMove(e));
    element.addEventListener('pointerup', (e) => this.pointerUp(e));
    element.addEventListener('pointercancel', (e) => this.pointerUp(e));
    element.addEventListener('contextmenu', (e) => e.preventDefault());
    element.addEventListener('wheel', (e) => this.wheel(e), { passive: false });
    element.addEventListener('keydown', (e) => this.keyDown(e));
    element.addEventListener('keyup', (e) => this.keys.delete(e.code));
    element.addEventListener('blur', () => this.keys.clear());
  }

  pointerDown(e) {
    if (!this.getCamera()) return;
    this.element.focus();
    const pan = e.button === 2 || e.button === 1 || e.shiftKey;
    this.drag = { mode: pan ? 'pan' : 'orbit', x: e.clientX, y: e.clientY, pointerId: e.pointerId };
    this.element.setPointerCapture(e.pointerId);
    this.element.classList.add('dragging');
    e.preventDefault();
  }

  pointerMove(e) {
    const camera = this.getCamera();
    if (!this.drag || e.pointerId !== this.drag.pointerId || !camera) return;
    const dx = e.clientX - this.drag.x;
    const dy = e.clientY - this.drag.y;
    if (dx === 0 && dy === 0) return;
    this.drag.x = e.clientX;
    this.drag.y = e.clientY;
    if (this.drag.mode === 'orbit') camera.orbit(dx, dy);
    else camera.pan(dx, dy, this.element.clientHeight);
    this.onChange();
  }

  pointerUp(e) {
    if (!this.drag || e.pointerId !== this.drag.pointerId) return;
    this.drag = null;
    this.element.classList.remove('dragging');
  }

  wheel(e) {
    const camera = this.getCamera();
    if (!camera) return;
    e.preventDefault();
    // Lines or pages (deltaMode 1, 2) count as steps; pixels are about 100 to a notch.
    const steps = e.deltaMode === 0 ? e.deltaY / 100 : Math.sign(e.deltaY);
    camera.zoom(steps);
    this.onChange();
  }

  keyDown(e) {
    const camera = this.getCamera();
    if (!camera || e.ctrlKey || e.metaKey || e.altKey) return;
    if (e.code === 'KeyR') {
      camera.reset();
      this.onChange();
      return;
    }
    if (!WALK_KEYS[e.code]) return;
    e.preventDefault(); // arrows would scroll the page
    this.fast = e.shiftKey;
    this.keys.add(e.code);
    if (!this.ticking) {
      this.ticking = true;
      this.lastTick = performance.now();
      requestAnimationFrame((t) => this.tick(t));
    }
  }

  // One step of walking per animation frame while a walk key is held.
  tick(now) {
    const camera = this.getCamera();
    if (this.keys.size === 0 || !camera) {
      this.ticking = false;
      return;
    }
    const dt = Math.min((now - this.lastTick) / 1000, 0.1);
    this.lastTick = now;
    const move = [0, 0, 0];
    for (const code of this.keys) WALK_KEYS[code].forEach((v, i) => (move[i] += v));
    const step = camera.walkSpeed() * dt * (this.fast ? 4 : 1);
    if (step > 0 && move.some((v) => v !== 0)) {
      camera.walk(move[0] * step, move[1] * step, move[2] * step);
      this.onChange();
    }
    requestAnimationFrame((t) => this.tick(t));
  }
}
