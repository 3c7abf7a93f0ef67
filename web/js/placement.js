// Where the Assets panel's Insert puts an uploaded mesh in a scene (docs/scene-format.md, "mesh"):
// a shape {"type": "mesh", "asset": id, "material", "transform": {"scale", "translate"}} built from
// the asset's bounds (in the file's own units) and the scene's camera.
//
// The choice: the mesh's largest side becomes a third of the distance from the camera to its
// look_at, and the center of its bounds goes to look_at. look_at is what the camera frames at the
// image's center, and at a third of the distance the mesh fills about half the height of the
// default 40° view, so it is in the picture, neither a speck nor clipped, whatever units the file
// and the scene use (the teapot is 6 units wide, the bunny 0.15). It is centered rather than set
// down on a floor: finding the surface below look_at would mean tracing rays through the scene
// here, and a user moves it with `translate` once it is in view.

/** The shape to insert for `asset` (GET /api/assets/{id}) into `scene` (parsed JSON), and the
 *  materials to add to the scene first ({} when it has one to use). Throws an Error saying what
 *  the scene lacks when it has no camera to place the mesh by. */
export function meshShapeFor(scene, asset) {
  const camera = scene?.camera;
  if (!isPoint(camera?.position) || !isPoint(camera?.look_at))
    throw new Error('the scene needs a camera with position and look_at to place a mesh');
  const {min, max} = asset.bounds;
  const size = max.map((v, i) => v - min[i]);
  const largest = Math.max(...size);
  const distance = Math.hypot(...camera.look_at.map((v, i) => v - camera.position[i]));
  const scale = largest > 0 ? distance / 3 / largest : 1;
  const center = min.map((v, i) => (v + max[i]) / 2);
  const translate = camera.look_at.map((v, i) => v - scale * center[i]);
  const [material, added] = materialFor(scene.materials);
  return {
    shape: {type: 'mesh', asset: asset.id, material,
      transform: {scale: round(scale), translate: translate.map(round)}},
    materials: added ? {[material]: added} : {},
  };
}

// Four significant digits keep the editor readable; they move the mesh by 0.05% of its size.
const round = x => Number(x.toPrecision(4));

const isPoint = p => Array.isArray(p) && p.length === 3 && p.every(Number.isFinite);

const emits = m => Array.isArray(m?.emission) && m.emission.some(v => v > 0);

// "white" if the scene has it, else its first diffuse material that does not emit, else any that
// does not emit; a scene with none gets a plain diffuse one ([name, material to add]).
function materialFor(materials) {
  const entries = Object.entries(materials && typeof materials === 'object' ? materials : {});
  const plain = entries.filter(([, m]) => !emits(m));
  const pick = plain.find(([n, m]) => n === 'white' && m?.type === 'diffuse') ||
    plain.find(([, m]) => m?.type === 'diffuse') || plain[0];
  if (pick) return [pick[0], null];
  let name = 'mesh';
  for (let i = 2; name in (materials || {}); i++) name = `mesh-${i}`;
  return [name, {type: 'diffuse', albedo: [0.8, 0.8, 0.8]}];
}
