//! Wavefront OBJ output: a group per building, faces triangulated, in the
//! source coordinates of the cloud.

use std::fmt::Write as _;
use std::path::Path;

use super::{ReconstructError, Reconstruction};

/// The reconstruction as OBJ text.
pub fn obj_text(rec: &Reconstruction) -> String {
    let mut s = String::from("# skyground LoD2 reconstruction\n");
    let mut next = 1usize;
    for m in &rec.models {
        let _ = writeln!(s, "o building_{}\ng building_{}", m.id, m.id);
        let tris = m.shell.triangles();
        for (t, _) in &tris {
            for p in t {
                let _ = writeln!(
                    s,
                    "v {:.3} {:.3} {:.3}",
                    p[0] + rec.origin[0],
                    p[1] + rec.origin[1],
                    p[2] + rec.origin[2]
                );
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
    std::fs::write(path, obj_text(rec)).map_err(|source| ReconstructError::Write {
        what: path.display().to_string(),
        source,
    })
}
