// vpsim's 3D view of a run: the cured surface coloured by its signed deviation from the model
// and the model itself, rotatable (OrbitControls), the model toggleable, a clipping plane at any
// layer. A classic script: the data comes from mesh3d.js (window.VPSIM_MESH), loaded before it,
// because Chromium blocks fetch() and ES modules on file://. Renders on demand; the canvas gets
// data-rendered="1" once the first frame is drawn.
(function () {
  'use strict';
  var canvas = document.getElementById('view3d');
  var status = document.getElementById('view3d-status');
  function say(text) { if (status) status.textContent = text; }
  if (!canvas) return;
  if (!window.THREE || !window.VPSIM_MESH) { say('The 3D view could not load its scripts.'); return; }
  var data = window.VPSIM_MESH;

  function decode(text, Type) {
    var bin = atob(text), bytes = new Uint8Array(bin.length);
    for (var i = 0; i < bin.length; ++i) bytes[i] = bin.charCodeAt(i);
    return new Type(bytes.buffer);
  }
  // Blue (inside the model) - white - red (outside), the figures' diverging scale.
  function diverging(t, out, k) {
    t = Math.max(-1, Math.min(1, t));
    var a = Math.abs(t), w = 0.97;
    var end = t < 0 ? [0.13, 0.40, 0.67] : [0.70, 0.09, 0.17];
    out[k] = w + (end[0] - w) * a; out[k + 1] = w + (end[1] - w) * a; out[k + 2] = w + (end[2] - w) * a;
  }
  function geometry(mesh) {
    var g = new THREE.BufferGeometry();
    var set = (g.setAttribute || g.addAttribute).bind(g);
    set('position', new THREE.BufferAttribute(decode(mesh.positions, Float32Array), 3));
    g.setIndex(new THREE.BufferAttribute(decode(mesh.indices, Uint32Array), 1));
    g.computeVertexNormals();
    return { g: g, set: set };
  }

  var renderer;
  try {
    renderer = new THREE.WebGLRenderer({ canvas: canvas, antialias: true, preserveDrawingBuffer: true });
  } catch (e) { say('WebGL is not available in this browser: no 3D view.'); return; }
  renderer.setPixelRatio(window.devicePixelRatio || 1);
  renderer.localClippingEnabled = true;
  renderer.setClearColor(0xf4f4f4);
  var scene = new THREE.Scene();
  var clip = new THREE.Plane(new THREE.Vector3(0, 0, -1), 1e9);

  var cured = geometry(data.cured);
  var dev = decode(data.deviation_um, Float32Array), colours = new Float32Array(dev.length * 3);
  for (var i = 0; i < dev.length; ++i) diverging(dev[i] / data.limit_um, colours, 3 * i);
  cured.set('color', new THREE.BufferAttribute(colours, 3));
  var curedMesh = new THREE.Mesh(cured.g, new THREE.MeshLambertMaterial({
    vertexColors: THREE.VertexColors, side: THREE.DoubleSide, clippingPlanes: [clip] }));
  scene.add(curedMesh);

  var model = geometry(data.model);
  var modelGroup = new THREE.Group();
  modelGroup.add(new THREE.Mesh(model.g, new THREE.MeshLambertMaterial({
    color: 0x888888, transparent: true, opacity: 0.25, depthWrite: false,
    side: THREE.DoubleSide, clippingPlanes: [clip] })));
  modelGroup.add(new THREE.LineSegments(new THREE.EdgesGeometry(model.g, 20),
    new THREE.LineBasicMaterial({ color: 0x222222, clippingPlanes: [clip] })));
  scene.add(modelGroup);

  cured.g.computeBoundingSphere();
  var sphere = cured.g.boundingSphere;
  var radius = Math.max(sphere.radius, 1e-3);
  var camera = new THREE.PerspectiveCamera(35, canvas.clientWidth / canvas.clientHeight,
                                           radius / 100, radius * 100);
  camera.up.set(0, 0, 1);
  camera.position.set(sphere.center.x + 2.2 * radius, sphere.center.y - 2.6 * radius,
                      sphere.center.z + 1.8 * radius);
  scene.add(new THREE.AmbientLight(0xffffff, 0.55));
  var light = new THREE.DirectionalLight(0xffffff, 0.6);
  camera.add(light);
  light.position.set(1, 1, 2);
  scene.add(camera);

  var controls = new THREE.OrbitControls(camera, canvas);
  controls.target.copy(sphere.center);
  controls.update();

  var pending = false;
  function render() {
    pending = false;
    var w = canvas.clientWidth, h = canvas.clientHeight;
    if (canvas.width !== Math.floor(w * renderer.getPixelRatio())) {
      renderer.setSize(w, h, false);
      camera.aspect = w / h;
      camera.updateProjectionMatrix();
    }
    renderer.render(scene, camera);
    canvas.setAttribute('data-rendered', '1');
  }
  function request() { if (!pending) { pending = true; requestAnimationFrame(render); } }
  controls.addEventListener('change', request);
  window.addEventListener('resize', request);

  var showModel = document.getElementById('view3d-model');
  if (showModel) showModel.addEventListener('change', function () {
    modelGroup.visible = showModel.checked; request(); });
  var slider = document.getElementById('view3d-clip'), label = document.getElementById('view3d-clip-label');
  var layers = Math.max(1, Math.round(data.height_mm / data.layer_mm));
  if (slider) {
    slider.max = String(layers);
    slider.value = String(layers);
    slider.addEventListener('input', function () {
      var k = Number(slider.value), z = k * data.layer_mm;
      clip.constant = k >= layers ? 1e9 : z;
      if (label) label.textContent = k >= layers ? 'whole part' :
        'cut at the top of layer ' + k + ' (z = ' + z.toFixed(3) + ' mm)';
      request();
    });
  }
  render();
})();
