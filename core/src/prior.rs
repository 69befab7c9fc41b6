//! A real aerial survey as the mission's prior (in place of the simulated
//! airborne survey): its tiles joined into one cloud, its CRS checked
//! against the city model's, and its extent against the model's, all in the
//! model's local frame so completeness is measured exactly as for the
//! simulated prior.

use thiserror::Error;

use crate::cloud::Cloud;
use crate::crs::Crs;
use crate::scene::Window;

/// Why tiles cannot be one survey, or a survey the prior of a city model.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum PriorError {
    /// No tile was given.
    #[error("no tile given")]
    NoTiles,
    /// A tile holds no points.
    #[error("tile {tile} holds no points")]
    EmptyTile {
        /// The tile's name.
        tile: String,
    },
    /// Two tiles name different horizontal CRSs.
    #[error(
        "tiles {first} ({first_crs}) and {tile} ({tile_crs}) are in different horizontal CRSs: reproject them to one CRS first"
    )]
    TileCrs {
        /// The first tile.
        first: String,
        /// Its CRS.
        first_crs: String,
        /// The tile that differs.
        tile: String,
        /// Its CRS.
        tile_crs: String,
    },
    /// The survey's horizontal CRS is not the city model's.
    #[error(
        "the prior is in {prior} but the city model in {model}: their horizontal CRSs differ (EPSG:{prior_h} vs EPSG:{model_h}); reproject the survey to EPSG:{model_h} first (e.g. pdal translate with filters.reprojection)"
    )]
    CrsMismatch {
        /// The prior's CRS.
        prior: String,
        /// The model's CRS.
        model: String,
        /// The prior's horizontal EPSG code.
        prior_h: u32,
        /// The model's horizontal EPSG code.
        model_h: u32,
    },
    /// The survey and the model share no ground.
    #[error(
        "the prior covers x {:.1}..{:.1}, y {:.1}..{:.1} and the city model x {:.1}..{:.1}, y {:.1}..{:.1} (source coordinates): they do not overlap; are they of the same place and in the same CRS?",
        prior.min[0], prior.max[0], prior.min[1], prior.max[1], model.min[0], model.max[0], model.min[1], model.max[1]
    )]
    NoOverlap {
        /// The prior's xy extent, source coordinates.
        prior: Window,
        /// The model's xy extent, source coordinates.
        model: Window,
    },
}

/// How the prior's CRS relates to the model's.
#[derive(Debug, Clone, PartialEq)]
pub enum CrsCheck {
    /// Both name this horizontal EPSG code.
    Same(u32),
    /// Both name a CRS, neither with a code we can compare, or the same
    /// CRS without a code: taken as equal.
    Unchecked,
    /// The prior names no CRS: taken to be the model's (named here, if any).
    PriorUnknown(Option<String>),
    /// The model names no CRS: taken to be the prior's.
    ModelUnknown(String),
}

/// Checks that the prior and the model share their horizontal CRS (their
/// heights may be in different vertical datums: AHN and 3DBAG both use NAP,
/// but the check is horizontal only).
pub fn check_crs(prior: Option<&Crs>, model: Option<&Crs>) -> Result<CrsCheck, PriorError> {
    match (prior, model) {
        (None, m) => Ok(CrsCheck::PriorUnknown(m.map(Crs::label))),
        (Some(p), None) => Ok(CrsCheck::ModelUnknown(p.label())),
        (Some(p), Some(m)) => match (p.horizontal_epsg(), m.horizontal_epsg()) {
            (Some(a), Some(b)) if a == b => Ok(CrsCheck::Same(a)),
            (Some(a), Some(b)) => Err(PriorError::CrsMismatch {
                prior: p.label(),
                model: m.label(),
                prior_h: a,
                model_h: b,
            }),
            _ => Ok(CrsCheck::Unchecked),
        },
    }
}

/// The tiles as one cloud in the first tile's frame; every tile must hold
/// points and name the first tile's horizontal CRS (or none at all).
pub fn join_tiles(tiles: &[(String, Cloud)]) -> Result<Cloud, PriorError> {
    let ((first_name, first), rest) = tiles.split_first().ok_or(PriorError::NoTiles)?;
    for (name, c) in tiles {
        if c.is_empty() {
            return Err(PriorError::EmptyTile { tile: name.clone() });
        }
    }
    let mut out = first.clone();
    for (name, c) in rest {
        same_crs((first_name, first), (name, c))?;
        append(&mut out, &to_frame(c, first.origin));
    }
    Ok(out)
}

/// Tiles of one survey name one horizontal CRS (or none).
pub fn same_crs(first: (&str, &Cloud), tile: (&str, &Cloud)) -> Result<(), PriorError> {
    let h = |c: &Cloud| c.crs.as_ref().and_then(Crs::horizontal_epsg);
    let label = |c: &Cloud| c.crs.as_ref().map_or("no CRS".to_string(), Crs::label);
    if h(tile.1) == h(first.1) {
        return Ok(());
    }
    Err(PriorError::TileCrs {
        first: first.0.to_owned(),
        first_crs: label(first.1),
        tile: tile.0.to_owned(),
        tile_crs: label(tile.1),
    })
}

/// `tile` followed by the points of `others` that lie within `buffer`
/// metres of its xy extent (in plan) but outside it, in its frame: what is
/// computed near its edges then sees across them, and a delivery whose
/// tiles overlap gives no point twice. The tile's own points stay the first
/// `tile.1.len()`; every other tile must name its horizontal CRS.
pub fn with_buffer(
    tile: &(String, Cloud),
    others: &[(String, Cloud)],
    buffer: f32,
) -> Result<Cloud, PriorError> {
    let (name, own) = tile;
    let (lo, hi) = own
        .bounds()
        .ok_or_else(|| PriorError::EmptyTile { tile: name.clone() })?;
    let within = |x: f32, y: f32, m: f32| {
        x >= lo[0] - m && x <= hi[0] + m && y >= lo[1] - m && y <= hi[1] + m
    };
    let mut parts = vec![tile.clone()];
    for (other_name, c) in others {
        same_crs((name, own), (other_name, c))?;
        let shift = [0, 1].map(|k| (c.origin[k] - own.origin[k]) as f32);
        let rows: Vec<usize> = (0..c.len())
            .filter(|&i| {
                let [x, y] = [0, 1].map(|k| c.xyz[i][k] + shift[k]);
                within(x, y, buffer) && !within(x, y, 0.0)
            })
            .collect();
        if !rows.is_empty() {
            parts.push((other_name.clone(), c.subset(&rows)));
        }
    }
    join_tiles(&parts)
}

/// Appends `b`'s points (in `a`'s frame) to `a`; a column either lacks is
/// dropped, so the joined cloud never has columns of the wrong length.
fn append(a: &mut Cloud, b: &Cloud) {
    fn join<T: Copy>(x: &mut Option<Vec<T>>, y: &Option<Vec<T>>) {
        match (x.as_mut(), y) {
            (Some(x), Some(y)) => x.extend_from_slice(y),
            _ => *x = None,
        }
    }
    a.xyz.extend_from_slice(&b.xyz);
    join(&mut a.intensity, &b.intensity);
    join(&mut a.label, &b.label);
    join(&mut a.building, &b.building);
    join(&mut a.return_number, &b.return_number);
    join(&mut a.number_of_returns, &b.number_of_returns);
}

/// The cloud re-expressed around `origin` (metres; e.g. a scene's origin),
/// every column kept.
pub fn to_frame(cloud: &Cloud, origin: [f64; 3]) -> Cloud {
    let shift = [0, 1, 2].map(|k| cloud.origin[k] - origin[k]);
    let mut out = cloud.clone();
    for p in &mut out.xyz {
        for k in 0..3 {
            p[k] = (f64::from(p[k]) + shift[k]) as f32;
        }
    }
    out.origin = origin;
    out
}

/// The cloud as it goes out on `/aerial_cloud`: without the producer's
/// classes and building ids (the scene_classifier labels it), with its
/// echoes and intensities (features the classifier uses).
pub fn unlabelled(cloud: &Cloud) -> Cloud {
    Cloud {
        label: None,
        building: None,
        ..cloud.clone()
    }
}

/// The xy extent of a cloud, local frame (`None` when empty or degenerate).
pub fn extent_xy(cloud: &Cloud) -> Option<Window> {
    let (lo, hi) = cloud.bounds()?;
    Window::new(
        f64::from(lo[0]),
        f64::from(lo[1]),
        f64::from(hi[0]),
        f64::from(hi[1]),
    )
    .ok()
}

/// The part of the model's extent the prior covers (both local, same frame
/// whose origin is `origin`); an error naming both extents in source
/// coordinates when they do not overlap.
pub fn overlap(prior: &Window, model: &Window, origin: [f64; 3]) -> Result<Window, PriorError> {
    let lo = [0, 1].map(|k| prior.min[k].max(model.min[k]));
    let hi = [0, 1].map(|k| prior.max[k].min(model.max[k]));
    Window::new(lo[0], lo[1], hi[0], hi[1]).map_err(|_| {
        let src = |w: &Window| Window {
            min: [w.min[0] + origin[0], w.min[1] + origin[1]],
            max: [w.max[0] + origin[0], w.max[1] + origin[1]],
        };
        PriorError::NoOverlap {
            prior: src(prior),
            model: src(model),
        }
    })
}

/// The window a mission on this prior runs in: the prior's extent grown by
/// `margin` metres (buildings at its edge are kept whole by the crop).
pub fn mission_window(prior: &Window, margin: f64) -> Window {
    let m = margin.max(0.0);
    Window {
        min: [prior.min[0] - m, prior.min[1] - m],
        max: [prior.max[0] + m, prior.max[1] + m],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cloud(origin: [f64; 3], xyz: Vec<[f32; 3]>, crs: Option<Crs>) -> Cloud {
        Cloud {
            label: Some(vec![6; xyz.len()]),
            return_number: Some(vec![1; xyz.len()]),
            number_of_returns: Some(vec![2; xyz.len()]),
            xyz,
            origin,
            crs,
            ..Cloud::default()
        }
    }

    #[test]
    fn rd_new_and_rd_new_plus_nap_share_their_horizontal_crs() {
        let rd = Crs::from_epsg(28992).unwrap();
        let rd_nap = Crs::from_epsg(7415).unwrap();
        assert_eq!(rd_nap.horizontal_epsg(), Some(28992));
        assert_eq!(
            check_crs(Some(&rd), Some(&rd_nap)).unwrap(),
            CrsCheck::Same(28992)
        );
        let swiss = Crs::from_epsg(2056).unwrap();
        let e = check_crs(Some(&swiss), Some(&rd_nap)).unwrap_err();
        assert!(
            matches!(
                e,
                PriorError::CrsMismatch {
                    prior_h: 2056,
                    model_h: 28992,
                    ..
                }
            ),
            "{e}"
        );
        assert!(e.to_string().contains("reproject"), "{e}");
        assert!(matches!(
            check_crs(None, Some(&rd_nap)).unwrap(),
            CrsCheck::PriorUnknown(Some(_))
        ));
    }

    #[test]
    fn tiles_join_in_the_first_tiles_frame() {
        let a = cloud([1000.0, 2000.0, 0.0], vec![[1.0, 2.0, 3.0]], None);
        let b = cloud([1100.0, 2000.0, 0.0], vec![[5.0, 0.5, 1.0]], None);
        let j = join_tiles(&[("a".into(), a), ("b".into(), b)]).unwrap();
        assert_eq!(j.xyz, vec![[1.0, 2.0, 3.0], [105.0, 0.5, 1.0]]);
        assert_eq!(j.number_of_returns.as_deref(), Some(&[2u8, 2][..]));
        let mut c = cloud(
            [0.0; 3],
            vec![[0.0; 3]],
            Some(Crs::from_epsg(2056).unwrap()),
        );
        let d = cloud(
            [0.0; 3],
            vec![[0.0; 3]],
            Some(Crs::from_epsg(28992).unwrap()),
        );
        assert!(matches!(
            join_tiles(&[("c".into(), c.clone()), ("d".into(), d)]),
            Err(PriorError::TileCrs { .. })
        ));
        c.xyz.clear();
        assert!(matches!(
            join_tiles(&[("c".into(), c)]),
            Err(PriorError::EmptyTile { .. })
        ));
        assert_eq!(join_tiles(&[]), Err(PriorError::NoTiles));
    }

    #[test]
    fn a_buffer_adds_the_neighbours_points_near_the_edge_once() {
        // Tile a: x 0..10 m at origin 1000; b starts 5 m inside a (overlap)
        // and runs to 40 m; c lies 200 m away.
        let row = |xs: &[f32]| xs.iter().map(|&x| [x, 1.0, 0.0]).collect::<Vec<_>>();
        let a = cloud([1000.0, 0.0, 0.0], row(&[0.0, 10.0]), None);
        let b = cloud(
            [1005.0, 0.0, 0.0],
            row(&[0.0, 4.0, 6.0, 9.0, 14.0, 35.0]),
            None,
        );
        let c = cloud([1200.0, 0.0, 0.0], row(&[0.0]), None);
        let others = [("b".to_string(), b), ("c".to_string(), c)];
        let j = with_buffer(&("a".into(), a.clone()), &others, 10.0).unwrap();
        // a's own points first; b's at x 11, 14 and 19 (within 10 m beyond
        // a's edge at 10); b's 5 and 9 are inside a, b's 40 and c too far.
        let xs: Vec<f32> = j.xyz.iter().map(|p| p[0]).collect();
        assert_eq!(xs, vec![0.0, 10.0, 11.0, 14.0, 19.0]);
        assert_eq!(j.origin, a.origin);
        let d = cloud([0.0; 3], row(&[0.0]), Some(Crs::from_epsg(2056).unwrap()));
        let far = [("d".to_string(), d)];
        assert!(matches!(
            with_buffer(&("a".into(), a), &far, 10.0),
            Err(PriorError::TileCrs { .. })
        ));
    }

    #[test]
    fn unlabelled_keeps_echoes_and_frames_shift_exactly() {
        let c = cloud([84_800.0, 447_400.0, 0.0], vec![[10.0, 20.0, 1.5]], None);
        let u = unlabelled(&c);
        assert!(u.label.is_none() && u.building.is_none());
        assert_eq!(u.number_of_returns, c.number_of_returns);
        let f = to_frame(&c, [84_760.0, 447_426.0, -0.5]);
        assert_eq!(f.xyz, vec![[50.0, -6.0, 2.0]]);
        assert_eq!(f.source_coordinates(f.xyz[0]), [84_810.0, 447_420.0, 1.5]);
    }

    #[test]
    fn overlap_is_the_shared_part_and_none_is_an_error() {
        let p = Window::new(40.0, -10.0, 300.0, 220.0).unwrap();
        let m = Window::new(0.0, 0.0, 330.0, 320.0).unwrap();
        assert_eq!(
            overlap(&p, &m, [0.0; 3]).unwrap(),
            Window::new(40.0, 0.0, 300.0, 220.0).unwrap()
        );
        let far = Window::new(5000.0, 0.0, 5100.0, 100.0).unwrap();
        let e = overlap(&far, &m, [84_000.0, 447_000.0, 0.0]).unwrap_err();
        assert!(e.to_string().contains("x 89000.0..89100.0"), "{e}");
        assert_eq!(
            mission_window(&p, 20.0),
            Window::new(20.0, -30.0, 320.0, 240.0).unwrap()
        );
    }
}
