//! Wavefront OBJ output: a group per building, faces triangulated, in the
//! source coordinates and unit of the cloud (OBJ names neither).

use std::fmt::Write as _;
use std::path::Path;

use crate::reconstruct::{ReconstructError, Reconstruction};

/// The reconstruction as OBJ text.
pub fn obj_text(rec: &Reconstruction) -> String {
    let mut s = String::from("# skyground LoD2 reconstruction\n");
    let mut next = 1usize;
    let frame = rec.frame();
    for m in &rec.models {
        let _ = writeln!(s, "o building_{}\ng building_{}", m.id, m.id);
        let tris = m.shell.triangles();
        for (t, _) in &tris {
            for p in t {
                let q = frame.to_source(*p);
                let _ = writeln!(s, "v {:.3} {:.3} {:.3}", q[0], q[1], q[2]);
            }
        }
        for k in 0..tris.len() {
            let a = next + 3 * k;
            let _ = writeln!(s, "f {} {} {}", a, a + 1, a + 2);
        }
        next += 3 * tris.len();
    }
    s
}

/// Writes [`obj_text`] to `path`.
pub fn write_obj(path: &Path, rec: &Reconstruction) -> Result<(), ReconstructError> {
    crate::file::write(path, obj_text(rec)).map_err(|e| ReconstructError::Write {
        what: path.display().to_string(),
        source: e.source,
    })
}
