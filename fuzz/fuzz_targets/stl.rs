//! STL files, binary and ASCII, as every command that reads a mesh takes
//! them: the mesh, its XY index, and a query over the whole mesh that must
//! find every triangle. No input may panic.
#![no_main]

use kezuri_geom::{Mesh, XyIndex};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(mesh) = Mesh::from_stl(data) else { return };
    let Some((lo, hi)) = mesh.bounds() else { return };
    let index = XyIndex::new(&mesh);
    let mut found = index.query_box([lo.x, lo.y, hi.x, hi.y]);
    found.dedup();
    assert_eq!(found.len(), mesh.len(), "a query over the mesh's box misses triangles");
    let _ = index.query_disk([(lo.x + hi.x) / 2.0, (lo.y + hi.y) / 2.0], (hi.x - lo.x) / 4.0);
});
