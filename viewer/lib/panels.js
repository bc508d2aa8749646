// Several meshes side by side, seen by ONE camera: one WebGL canvas behind a row of panels,
// each panel drawn into its own viewport. Orbiting anywhere turns every panel together.
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { boundsOf, defaultView } from './mesh.js';

export class PanelView {
  /**
   * container: an element sized by the page; the view fills it with a row of equal panels.
   * Options: background (CSS colour), interactive (orbit controls), captionPosition ('top' or
   * 'bottom'), fov (degrees), preserveDrawingBuffer (for screenshots), lighterOnSoftware (when WebGL
   * is drawn by the CPU, see softwareWebGL(): no multisampling, and half the resolution between
   * setInteracting(true) and setInteracting(false); a GPU draws as without it).
   */
  constructor(container, { background = '#ffffff', interactive = true, captionPosition = 'bottom',
                           fov = 25, preserveDrawingBuffer = false, lighterOnSoftware = false } = {}) {
    this.container = container;
    this.container.classList.add('panel-view');
    this.canvas = document.createElement('canvas');
    this.canvas.className = 'panel-view-canvas';
    this.row = document.createElement('div');
    this.row.className = 'panel-view-row';
    container.append(this.canvas, this.row);
    this.captionPosition = captionPosition;
    // (a CPU-drawn frame of a 26k-vertex mesh at 1100 x 760 CSS pixels took 185 ms with 4x
    // multisampling, 73 ms without, 28 ms at half the resolution: headless Chromium, SwiftShader)
    this.software = lighterOnSoftware && softwareWebGL();
    this.renderer = new THREE.WebGLRenderer({ canvas: this.canvas, antialias: !this.software, preserveDrawingBuffer });
    this.pixelRatio = window.devicePixelRatio || 1;
    this.interacting = false;
    this.renderer.setPixelRatio(this.pixelRatio);
    this.renderer.setClearColor(new THREE.Color(background), 1);
    this.renderer.setScissorTest(true);
    this.camera = new THREE.PerspectiveCamera(fov, 1, 0.01, 100);
    this.panels = [];
    this.controls = null;
    if(interactive) {
      this.controls = new OrbitControls(this.camera, this.canvas);
      this.controls.enableDamping = false;
      this.controls.addEventListener('change', () => this.requestRender());
      this.controls.addEventListener('start', () => this.setInteracting(true));   // orbiting, panning, zooming
      this.controls.addEventListener('end', () => this.setInteracting(false));
    }
    this.renderCount = 0;
    this.listeners = [];
    this.pending = false;
    this.resizeObserver = new ResizeObserver(() => { this.resize(); this.requestRender(); });
    this.resizeObserver.observe(container);
  }

  /** Replaces the panels: [{ title, object }] (object: a THREE.Object3D, e.g. from createFieldMesh). */
  setPanels(panels) {
    for(const panel of this.panels) panel.element.remove();
    this.panels = panels.map(({ title, object }) => {
      const scene = new THREE.Scene();
      scene.add(new THREE.HemisphereLight(0xffffff, 0x808080, 1.1));
      const light = new THREE.DirectionalLight(0xffffff, 1.6);
      scene.add(light, light.target, object);
      // A panel: its caption above or below the port, the part of the canvas it draws into.
      const element = document.createElement('div');
      element.className = 'panel';
      const port = document.createElement('div');
      port.className = 'panel-port';
      const caption = document.createElement('div');
      caption.className = 'panel-caption';
      caption.textContent = title;
      if(this.captionPosition === 'top') element.append(caption, port);
      else element.append(port, caption);
      this.row.append(element);
      return { title, object, scene, light, element, port };
    });
    this.resize();
    this.requestRender();
    return this;
  }

  /** The bounding box of every panel's object. */
  bounds() { return boundsOf(this.panels.map((p) => p.object)); }

  /** The camera's axes for a view: back (target towards camera), up, right, trueUp. */
  viewBasis(box, direction = null, up = null) {
    const view = defaultView(box);
    const back = direction ? new THREE.Vector3().fromArray(direction).normalize() : view.direction;
    const upv = up ? new THREE.Vector3().fromArray(up).normalize() : view.up;
    const right = new THREE.Vector3().crossVectors(upv, back);
    if(right.lengthSq() < 1e-12) throw new Error('camera: the up vector is parallel to the viewing direction');
    right.normalize();
    return { back, up: upv, right, trueUp: new THREE.Vector3().crossVectors(back, right) };
  }

  /** Calls fn(point) for every vertex of every panel (world coordinates; the point is reused). */
  eachPoint(fn) {
    const p = new THREE.Vector3();
    for(const panel of this.panels)
      panel.object.traverse((o) => {
        const position = o.geometry && o.geometry.getAttribute('position');
        if(!position) return;
        o.updateMatrixWorld();
        for(let i = 0; i < position.count; ++i) fn(p.fromBufferAttribute(position, i).applyMatrix4(o.matrixWorld));
      });
  }

  /** Width / height of the panels' objects seen along a view (parallel projection; 1 if empty). */
  contentAspect({ direction = null, up = null } = {}) {
    const box = this.bounds();
    if(box.isEmpty()) return 1;
    const { right, trueUp } = this.viewBasis(box, direction, up);
    const lo = [Infinity, Infinity], hi = [-Infinity, -Infinity];
    this.eachPoint((p) => {
      const x = right.dot(p), y = trueUp.dot(p);
      lo[0] = Math.min(lo[0], x); hi[0] = Math.max(hi[0], x);
      lo[1] = Math.min(lo[1], y); hi[1] = Math.max(hi[1], y);
    });
    const w = hi[0] - lo[0], h = hi[1] - lo[1];
    return w > 0 && h > 0 ? w / h : 1;
  }

  /**
   * Points the camera at every panel's object from `direction` (target towards camera) with
   * `up` (defaults from defaultView() of the common bounding box), as close as the vertices
   * allow; `margin` > 1 leaves room around them.
   */
  fitCamera({ direction = null, up = null, margin = 1.06 } = {}) {
    const box = this.bounds();
    if(box.isEmpty()) return this;
    const { back, up: upv, right, trueUp } = this.viewBasis(box, direction, up);
    // Centre the projected extents (seen along the view axis), then back off until every vertex
    // is inside both the vertical and the horizontal field of view.
    const center = box.getCenter(new THREE.Vector3());
    const extent = (axis) => {
      let lo = Infinity, hi = -Infinity;
      this.eachPoint((p) => { const v = axis.dot(p) - axis.dot(center); lo = Math.min(lo, v); hi = Math.max(hi, v); });
      return (lo + hi) / 2;
    };
    center.addScaledVector(right, extent(right)).addScaledVector(trueUp, extent(trueUp));
    const tv = Math.tan(THREE.MathUtils.degToRad(this.camera.fov) / 2);
    const th = tv * this.camera.aspect;
    let distance = 0;
    const rel = new THREE.Vector3();
    this.eachPoint((p) => {
      rel.subVectors(p, center);
      const z = rel.dot(back);
      distance = Math.max(distance, z + margin * Math.abs(rel.dot(right)) / th, z + margin * Math.abs(rel.dot(trueUp)) / tv);
    });
    if(!(distance > 0)) distance = box.getSize(new THREE.Vector3()).length() || 1;
    this.camera.up.copy(upv);
    this.camera.position.copy(center).addScaledVector(back, distance);
    this.camera.near = distance / 100;
    this.camera.far = distance * 100;
    this.camera.lookAt(center);
    this.camera.updateProjectionMatrix();
    this.home = { position: this.camera.position.clone(), up: upv.clone(), target: center.clone() };
    if(this.controls) { this.controls.target.copy(center); this.controls.update(); }
    this.requestRender();
    return this;
  }

  /** The extent of every panel's vertices in normalised device coordinates: { x: [lo, hi], y: [lo, hi] }. */
  projectedExtent() {
    this.camera.updateMatrixWorld();
    const x = [Infinity, -Infinity], y = [Infinity, -Infinity];
    const p = new THREE.Vector3();
    this.eachPoint((q) => {
      p.copy(q).project(this.camera);
      x[0] = Math.min(x[0], p.x); x[1] = Math.max(x[1], p.x);
      y[0] = Math.min(y[0], p.y); y[1] = Math.max(y[1], p.y);
    });
    return { x, y };
  }

  /** Back to the view of the last fitCamera(). */
  resetView() {
    if(!this.home) return;
    this.camera.position.copy(this.home.position);
    this.camera.up.copy(this.home.up);
    this.camera.lookAt(this.home.target);
    if(this.controls) { this.controls.target.copy(this.home.target); this.controls.update(); }
    this.requestRender();
  }

  resize() {
    const width = this.container.clientWidth, height = this.container.clientHeight;
    if(width === 0 || height === 0) return;
    this.renderer.setSize(width, height, false);
    const first = this.panels[0];
    if(first) {
      const rect = first.port.getBoundingClientRect();
      if(rect.width > 0 && rect.height > 0) {
        this.camera.aspect = rect.width / rect.height;
        this.camera.updateProjectionMatrix();
      }
    }
  }

  /**
   * What is under a point of the page (client coordinates): { panel (index), object, point,
   * face, vertex (the face's corner nearest to the hit) } or null.
   */
  pick(clientX, clientY) {
    for(const [index, panel] of this.panels.entries()) {
      const rect = panel.port.getBoundingClientRect();
      if(clientX < rect.left || clientX >= rect.right || clientY < rect.top || clientY >= rect.bottom) continue;
      const ndc = new THREE.Vector2(2 * (clientX - rect.left) / rect.width - 1, 1 - 2 * (clientY - rect.top) / rect.height);
      const raycaster = new THREE.Raycaster();
      raycaster.setFromCamera(ndc, this.camera);
      const hit = raycaster.intersectObject(panel.object, true)[0];
      if(!hit || !hit.face) return null;
      const position = hit.object.geometry.getAttribute('position');
      const local = hit.object.worldToLocal(hit.point.clone());
      const corners = [hit.face.a, hit.face.b, hit.face.c];
      const distance = (v) => local.distanceToSquared(new THREE.Vector3().fromBufferAttribute(position, v));
      const vertex = corners.reduce((best, v) => (distance(v) < distance(best) ? v : best));
      return { panel: index, object: hit.object, point: hit.point, face: hit.faceIndex, vertex };
    }
    return null;
  }

  /**
   * Marks the start (true) or the end (false) of an interaction, e.g. a drag: with software WebGL
   * and lighterOnSoftware, frames are drawn at half the resolution meanwhile, and the end draws
   * one at the full resolution. Otherwise nothing changes.
   */
  setInteracting(on) {
    if(!this.software || this.interacting === on) return;
    this.interacting = on;
    this.renderer.setPixelRatio(on ? this.pixelRatio / 2 : this.pixelRatio);   // (resizes the drawing buffer)
    this.requestRender();
  }

  /** Calls `callback(renderCount)` after each render (e.g. to mark a page as rendered). */
  onRender(callback) { this.listeners.push(callback); }

  /** Schedules one render at the next animation frame (several requests make one render). */
  requestRender() {
    if(this.pending) return;
    this.pending = true;
    requestAnimationFrame(() => { this.pending = false; this.render(); });
  }

  /** Renders every panel now. */
  render() {
    const canvasRect = this.canvas.getBoundingClientRect();
    const target = this.controls ? this.controls.target : null;
    this.renderer.setScissorTest(false);
    this.renderer.clear();
    this.renderer.setScissorTest(true);
    for(const panel of this.panels) {
      const rect = panel.port.getBoundingClientRect();
      const left = rect.left - canvasRect.left, bottom = canvasRect.bottom - rect.bottom;
      if(rect.width <= 0 || rect.height <= 0) continue;
      this.renderer.setViewport(left, bottom, rect.width, rect.height);
      this.renderer.setScissor(left, bottom, rect.width, rect.height);
      // A head light: shading follows the camera, so turning the objects keeps them lit.
      panel.light.position.copy(this.camera.position);
      if(target) panel.light.target.position.copy(target);
      else panel.light.target.position.copy(this.home ? this.home.target : new THREE.Vector3());
      panel.light.target.updateMatrixWorld();
      this.renderer.render(panel.scene, this.camera);
    }
    ++this.renderCount;
    for(const listener of this.listeners) listener(this.renderCount);
  }

  dispose() {
    this.resizeObserver.disconnect();
    if(this.controls) this.controls.dispose();
    for(const panel of this.panels) panel.object.traverse((o) => {
      if(o.geometry) o.geometry.dispose();
      if(o.material) o.material.dispose();
    });
    this.renderer.dispose();
    this.container.replaceChildren();
  }
}

/**
 * Whether WebGL is drawn by the CPU here (SwiftShader, llvmpipe, softpipe, Microsoft's Basic Render
 * Driver: a browser without a usable GPU, or one run with --disable-gpu), from the renderer's name
 * (a throwaway context).
 */
export function softwareWebGL() {
  const gl = document.createElement('canvas').getContext('webgl2');
  if(!gl) return false;
  const info = gl.getExtension('WEBGL_debug_renderer_info');
  const name = String(gl.getParameter(info ? info.UNMASKED_RENDERER_WEBGL : gl.RENDERER));
  const lose = gl.getExtension('WEBGL_lose_context');
  if(lose) lose.loseContext();
  return /swiftshader|llvmpipe|softpipe|software|basic render driver/i.test(name);
}
