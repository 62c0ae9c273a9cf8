//! STL files, binary and ASCII, as every command that reads a mesh takes
//! them: the mesh and its XY index. No input may panic.
#![no_main]

use kezuri_geom::{Mesh, XyIndex};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(mesh) = Mesh::from_stl(data) {
        let _ = mesh.bounds();
        let index = XyIndex::new(&mesh);
        let _ = index.cells();
    }
});
