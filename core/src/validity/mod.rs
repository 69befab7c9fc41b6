//! Solid validity: the ISO 19107 checks val3dity runs on a Solid, with
//! val3dity's error codes (ring 1xx, polygon 2xx, shell 3xx).
//!
//! Plain data in, plain data out: a [`Solid`] (vertices and shells of
//! surfaces of rings of vertex indices) gives a list of [`Finding`]s; an empty
//! list is a valid solid. As in val3dity, vertices closer than the snapping
//! tolerance are one vertex, and when any surface fails a ring or polygon
//! check no shell is checked as a shell (its topology would be meaningless).
//! Within the shell level, 302, 303 and 307 (along edges) stop the volume and
//! self-intersection checks; 305 does not, so two crossing cubes in one shell
//! give 305 and 306 where val3dity reports 305 alone.
//!
//! - [`codes`]: the codes and their val3dity names.
//! - `snap`: merging vertices on the snapping grid.
//! - `plane`: a surface's least-squares plane and its 2D frame.
//! - `surface`, `ring`, `polygon`: the ring and polygon checks of one surface.
//! - `triangulate`: a projected surface as triangles (spade's CDT).
//! - `shell`, `orientation`, `intersect`: the shell checks; `tritri` their
//!   triangle and segment contact tests.
//! - [`cityjson`]: reading a CityJSON Solid's `boundaries`.

pub mod cityjson;
pub mod codes;
mod intersect;
mod orientation;
mod plane;
mod polygon;
mod ring;
mod shell;
mod snap;
mod surface;
mod triangulate;
mod tritri;

#[cfg(test)]
mod tests;

pub use cityjson::{from_cityjson_geometry, solids_from_cityjson_geometry};
pub use codes::code_name;
pub use plane::flatness;

use serde::Serialize;

/// One surface: its rings (first outer, then inner), each a list of vertex indices, not repeating the first at the end.
pub type Surface = Vec<Vec<usize>>;

/// A solid: vertices and one or more shells (first exterior), each a list of surfaces.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Solid {
    /// Vertex positions in metres.
    pub vertices: Vec<[f64; 3]>,
    /// Shells: the first is the exterior, the others voids.
    pub shells: Vec<Vec<Surface>>,
}

/// The tolerances of the checks (val3dity's defaults).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Tolerances {
    /// Largest distance of a vertex from its surface's plane (203), m.
    pub planarity_m: f64,
    /// Largest angle between a surface's triangle and its plane (204), degrees.
    pub normals_deg: f64,
    /// Vertices closer than this are one vertex (val3dity's snap_tol), m.
    pub snap_m: f64,
}

impl Default for Tolerances {
    fn default() -> Self {
        Self {
            planarity_m: 0.01,
            normals_deg: 20.0,
            snap_m: 0.001,
        }
    }
}

/// A val3dity error: its code and where (shell index, surface index; `None` for the whole shell).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
pub struct Finding {
    /// val3dity's error code (see [`code_name`]).
    pub code: u16,
    /// Index of the shell in [`Solid::shells`].
    pub shell: usize,
    /// Index of the surface in its shell, when one surface is to blame.
    pub surface: Option<usize>,
}

impl Finding {
    /// val3dity's name of this finding's code.
    pub fn name(&self) -> &'static str {
        code_name(self.code)
    }
}

/// All findings of `s`, sorted and without repeats; empty when `s` is valid.
pub fn check_solid(s: &Solid, tol: &Tolerances) -> Vec<Finding> {
    if s.shells.is_empty() {
        return vec![Finding {
            code: codes::EMPTY_PRIMITIVE,
            shell: 0,
            surface: None,
        }];
    }
    let ids = snap::merge(&s.vertices, tol.snap_m);
    let mut findings = Vec::new();
    let mut faces = Vec::with_capacity(s.shells.len());
    for (si, shell) in s.shells.iter().enumerate() {
        let mut ok = Vec::with_capacity(shell.len());
        for (fi, rings) in shell.iter().enumerate() {
            match surface::check(&s.vertices, &ids, rings, tol) {
                Ok(face) => ok.push(face),
                Err(found) => findings.extend(found.into_iter().map(|code| Finding {
                    code,
                    shell: si,
                    surface: Some(fi),
                })),
            }
        }
        faces.push(ok);
    }
    // val3dity stops at the first level that fails: shells only when every surface passed.
    if findings.is_empty() {
        for (si, shell) in faces.iter().enumerate() {
            let codes = shell::check(&s.vertices, shell, si == 0, tol);
            findings.extend(codes.into_iter().map(|(code, surface)| Finding {
                code,
                shell: si,
                surface,
            }));
        }
    }
    findings.sort();
    findings.dedup();
    findings
}
