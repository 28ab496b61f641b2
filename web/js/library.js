// The viewer's library: the models of the catalogue, by group. The regular, convex uniform and
// star polychora come from the WebAssembly core (their names and Coxeter diagrams); prisms,
// duoprisms, round shapes and toratopes are specs of the parametric families with parameters
// that look good (every spec is one `cw4d` accepts too).

const PRISMS = [
  ['tetrahedral prism', 'prism:wythoff:x3o3o'],
  ['octahedral prism', 'prism:wythoff:x3o4o'],
  ['dodecahedral prism', 'prism:wythoff:x5o3o'],
  ['icosahedral prism', 'prism:wythoff:x3o5o'],
  ['truncated octahedral prism', 'prism:wythoff:o3x4x'],
  ['rhombicosidodecahedral prism', 'prism:wythoff:x5o3x'],
  ['pentagonal antiprismatic prism', 'prism:antiprism:5'],
  ['3,3-duoprism', 'duoprism:3,3'],
  ['3,4-duoprism', 'duoprism:3,4'],
  ['5,7-duoprism', 'duoprism:5,7'],
  ['6,6-duoprism', 'duoprism:6,6'],
  ['8,12-duoprism', 'duoprism:8,12'],
  ['20,20-duoprism', 'duoprism:20,20'],
];

const ROUND = [
  ['duocylinder', 'duocylinder:1,32'],
  ['cubinder', 'cubinder:1,32'],
  ['spherinder', 'spherinder:1,20'],
  ['spherone (cone over a sphere)', 'cone:sphere:1,16'],
  ['cylindrone (cone over a cylinder)', 'cone:cylinder:1,24'],
];

const TORATOPES = [
  ['spheritorus', 'spheritorus:2,0.7,16'],
  ['torisphere', 'torisphere:2,0.7,16'],
  ['ditorus', 'ditorus:3,1.6,0.5,12'],
  ['tiger', 'tiger:2,2,0.6,12'],
];

const OTHER = [
  ['cubic pyramid', 'pyramid:cube:3'],
  ['dual of the rectified 5-cell', 'dual:rectified 5-cell'],
  ['cube (3D: its sections are polygons)', 'cube:3'],
];

// [{group, entries: [{name, spec, diagram}]}] in display order.
export function libraryGroups(core) {
  const groups = new Map();
  const add = (group, name, spec, diagram = '') => {
    if (!groups.has(group)) groups.set(group, []);
    groups.get(group).push({ name, spec, diagram });
  };
  const listed = core.library();
  for (let i = 0; i < listed.length; ++i) {
    const e = listed[i];
    add(e.group, e.name, e.spec, e.diagram);
  }
  for (const [name, spec] of PRISMS) add('prisms and duoprisms', name, spec);
  for (const [name, spec] of ROUND) add('round', name, spec);
  for (const [name, spec] of TORATOPES) add('toratopes', name, spec);
  for (const [name, spec] of OTHER) add('more', name, spec);
  return [...groups].map(([group, entries]) => ({ group, entries }));
}
