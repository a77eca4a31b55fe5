// crslab serve: the arm in 3D (three.js), built from the MuJoCo model's body tree and shapes (/api/arm), posed
// by its DH angles from the frames the server streams (60 per simulated second), coloured by the safety envelope and the motor board.
// Dragging a link is the hand: the grabbed point and where the mouse holds it go to the server, which pulls
// the link there; letting go releases the arm.
"use strict";

window.CrsArm = (function () {
  function ArmView(host, shapes, onHand) {
    const T = window.CrsVendor.THREE;
    this.T = T;
    this.host = host;
    this.onHand = onHand;
    this.scene = new T.Scene();
    this.scene.background = new T.Color(0xf4f6f8);
    this.camera = new T.PerspectiveCamera(40, 1, 0.01, 20);
    this.camera.up.set(0, 0, 1); // MuJoCo's z is up
    this.target = new T.Vector3(0.15, 0, 0.25);
    this.orbit = new T.Spherical(1.6, 1.15, 0.9);
    if (shapes.view) { // a world's fixtures, all in view (crslab/serve/app.py's fixtures_view)
      this.target.set(...shapes.view.target);
      this.orbit = new T.Spherical(shapes.view.distance, shapes.view.phi, shapes.view.theta);
      this.camera.fov = shapes.view.fov_deg;
    }
    this.renderer = new T.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
    host.appendChild(this.renderer.domElement);
    this.scene.add(new T.AmbientLight(0xffffff, 0.7));
    const sun = new T.DirectionalLight(0xffffff, 1.6);
    sun.position.set(1, -1, 2);
    this.scene.add(sun);
    const grid = new T.GridHelper(1.2, 12, 0xb0b8c0, 0xd5dbe0);
    grid.rotation.x = Math.PI / 2;
    this.scene.add(grid);
    // the body tree: each body a group in its parent's, turned by its hinge; shapes hang in its frame
    this.joints = [];
    this.pickable = [];
    this.materials = [];
    const frames = [];
    shapes.bodies.forEach((body, i) => {
      const fixed = new T.Group();
      fixed.position.set(...body.pos);
      fixed.quaternion.set(...body.quat);
      let frame = fixed;
      if (body.joint) {
        const hinge = new T.Group();
        hinge.position.set(...body.joint.anchor);
        fixed.add(hinge);
        frame = new T.Group();
        frame.position.set(-body.joint.anchor[0], -body.joint.anchor[1], -body.joint.anchor[2]);
        hinge.add(frame);
        this.joints.push({ hinge, axis: new T.Vector3(...body.joint.axis), q: body.joint.q,
          minusSum: body.joint.minus_sum || null });
      }
      frame.userData.body = body.name;
      for (const s of body.shapes) {
        const mesh = new T.Mesh(this.geometry(s), this.material(s.rgba));
        if (s.name === "egg") this.egg = { mesh, z: s.pos[2], half: s.size[2] };
        mesh.position.set(...s.pos);
        mesh.quaternion.set(...s.quat);
        mesh.userData.body = body.name;
        frame.add(mesh);
        if (body.moving) this.pickable.push(mesh);
      }
      (i === 0 ? this.scene : frames[body.parent]).add(i === 0 ? frame : fixed);
      frames.push(frame);
    });
    this.raycaster = new T.Raycaster();
    this.drag = null;
    this.resize();
    new ResizeObserver(() => this.resize()).observe(host);
    this.listen();
    this.dirty = true;
  }

  ArmView.prototype.geometry = function (s) {
    const T = this.T;
    let g;
    if (s.kind === "capsule") g = new T.CapsuleGeometry(s.size[0], 2 * s.size[1], 6, 16);
    else if (s.kind === "cylinder") g = new T.CylinderGeometry(s.size[0], s.size[0], 2 * s.size[1], 24);
    else if (s.kind === "sphere") return new T.SphereGeometry(s.size[0], 24, 16);
    else if (s.kind === "ellipsoid") return new T.SphereGeometry(1, 24, 16).scale(s.size[0], s.size[1], s.size[2]);
    else return new T.BoxGeometry(2 * s.size[0], 2 * s.size[1], 2 * s.size[2]);
    g.rotateX(Math.PI / 2); // three's capsules and cylinders lie along y, MuJoCo's along z
    return g;
  };

  ArmView.prototype.material = function (rgba) {
    const m = new this.T.MeshStandardMaterial({ color: new this.T.Color(rgba[0], rgba[1], rgba[2]),
      roughness: 0.6, metalness: 0.1 });
    m.userData.base = m.color.clone();
    this.materials.push(m);
    return m;
  };

  ArmView.prototype.dispose = function () {
    this.renderer.dispose();
    this.renderer.domElement.remove();
    this.disposed = true;
  };

  ArmView.prototype.resize = function () {
    if (this.disposed) return;
    const w = this.host.clientWidth || 400, h = this.host.clientHeight || 300;
    this.renderer.setSize(w, h);
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
    this.dirty = true;
  };

  // One frame: [tick, 3 DH angles (rad), 3 motor angles, safety flag, motor board off]; in a world with
  // fixtures also [the egg's force (N), the scale (g), the egg broken (0/1)].
  ArmView.prototype.pose = function (frame) {
    for (const j of this.joints) {
      const angle = j.minusSum ? -(frame[1 + j.minusSum[0]] + frame[1 + j.minusSum[1]]) : frame[1 + j.q];
      j.hinge.quaternion.setFromAxisAngle(j.axis, angle);
    }
    if (this.egg && frame.length > 11) { // a broken egg lies flat on the scale
      this.egg.mesh.scale.set(1, 1, frame[11] ? 0.2 : 1);
      this.egg.mesh.position.z = frame[11] ? this.egg.z - 0.8 * this.egg.half : this.egg.z;
    }
    if (frame.length > 11 && this.onWorld) this.onWorld(frame[9], frame[10], frame[11]);
    const tint = frame[8] ? [0.55, 0.55, 0.55] : frame[7] ? [1.0, 0.35, 0.3] : null;
    for (const m of this.materials) {
      m.color.copy(m.userData.base);
      if (tint) m.color.multiply(new this.T.Color(...tint)).lerp(new this.T.Color(...tint), 0.35);
    }
    this.dirty = true;
  };

  ArmView.prototype.render = function () {
    if (!this.dirty) return;
    this.dirty = false;
    const offset = new this.T.Vector3().setFromSpherical(this.orbit);
    // Spherical is y-up: swap to z-up
    this.camera.position.set(this.target.x + offset.z, this.target.y + offset.x, this.target.z + offset.y);
    this.camera.lookAt(this.target);
    this.renderer.render(this.scene, this.camera);
  };

  ArmView.prototype.ray = function (e) {
    const r = this.renderer.domElement.getBoundingClientRect();
    const p = new this.T.Vector2(((e.clientX - r.left) / r.width) * 2 - 1, -((e.clientY - r.top) / r.height) * 2 + 1);
    this.raycaster.setFromCamera(p, this.camera);
    return this.raycaster;
  };

  ArmView.prototype.listen = function () {
    const el = this.renderer.domElement;
    el.addEventListener("pointerdown", (e) => {
      el.setPointerCapture(e.pointerId);
      const hit = this.ray(e).intersectObjects(this.pickable, false)[0];
      if (hit) {
        const group = hit.object.parent;
        group.updateWorldMatrix(true, false);
        const normal = new this.T.Vector3();
        this.camera.getWorldDirection(normal);
        this.drag = { body: hit.object.userData.body, anchor: group.worldToLocal(hit.point.clone()),
          plane: new this.T.Plane().setFromNormalAndCoplanarPoint(normal, hit.point), last: 0 };
        this.sendHand(hit.point, true);
      } else {
        this.turn = { x: e.clientX, y: e.clientY };
      }
    });
    el.addEventListener("pointermove", (e) => {
      if (this.drag) {
        const p = new this.T.Vector3();
        if (this.ray(e).ray.intersectPlane(this.drag.plane, p)) this.sendHand(p, false);
      } else if (this.turn) {
        this.orbit.theta -= (e.clientX - this.turn.x) * 0.01;
        this.orbit.phi = Math.min(3.0, Math.max(0.1, this.orbit.phi - (e.clientY - this.turn.y) * 0.01));
        this.turn = { x: e.clientX, y: e.clientY };
        this.dirty = true;
      }
    });
    const end = () => {
      if (this.drag) this.onHand(null);
      this.drag = null;
      this.turn = null;
    };
    el.addEventListener("pointerup", end);
    el.addEventListener("pointercancel", end);
    el.addEventListener("wheel", (e) => {
      e.preventDefault();
      this.orbit.radius = Math.min(5, Math.max(0.3, this.orbit.radius * (e.deltaY > 0 ? 1.1 : 0.9)));
      this.dirty = true;
    }, { passive: false });
  };

  ArmView.prototype.sendHand = function (target, now) {
    const t = performance.now();
    if (!now && t - this.drag.last < 30) return; // about 30 messages a second while dragging
    this.drag.last = t;
    const a = this.drag.anchor;
    this.onHand({ body: this.drag.body, anchor: [a.x, a.y, a.z], target: [target.x, target.y, target.z] });
  };

  return { ArmView };
})();
