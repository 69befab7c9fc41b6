//! The reference scene's buildings: a fixed street plan whose sizes and
//! heights vary with the seed.
//!
//! Four blocks around two 16 m streets (x, y ∈ [92, 108]):
//! - south-west: a podium with three towers, two boxes across a 2–4 m alley,
//!   a tall box, a park;
//! - south-east: a courtyard block, an L, four gable-roofed houses (one pair
//!   across a 2–4 m alley);
//! - north-west: a U, a slab on eight pillars (hollow base), a tall box, a
//!   low box;
//! - north-east: an L, a mid-rise box, two gable houses across an alley, a park.

use super::solids::{Rect, gable_house, podium_with_towers, prism, slab_on_pillars};
use super::terrain::ReferenceTerrain;
use crate::rng::Rng;
use crate::scene::builder::MeshPart;

/// How far walls reach below the lowest terrain point of their footprint (m),
/// so that no gap opens between a wall and the sloped ground.
const SINK: f64 = 0.5;

/// The shape of one building.
#[derive(Debug, Clone)]
enum Shape {
    /// A flat-roofed prism, optionally with holes (courtyards); height above ground.
    Prism {
        outline: Vec<[f64; 2]>,
        holes: Vec<Vec<[f64; 2]>>,
        height: f64,
    },
    /// A podium with towers; heights above ground.
    Podium {
        rect: Rect,
        height: f64,
        towers: Vec<(Rect, f64)>,
    },
    /// A slab on pillars; floor and roof heights above ground.
    Pillars { rect: Rect, floor: f64, height: f64 },
    /// A gable-roofed house; eave and ridge heights above ground.
    Gable {
        rect: Rect,
        eave: f64,
        ridge: f64,
        along_x: bool,
    },
}

/// One planned building.
#[derive(Debug, Clone)]
pub struct Plan {
    /// Object name (`building_NN_kind`).
    pub name: String,
    shape: Shape,
}

impl Plan {
    /// Outer footprint ring, counter-clockwise.
    pub fn outline(&self) -> Vec<[f64; 2]> {
        match &self.shape {
            Shape::Prism { outline, .. } => super::solids::ccw(outline),
            Shape::Podium { rect, .. }
            | Shape::Pillars { rect, .. }
            | Shape::Gable { rect, .. } => rect.ring(),
        }
    }

    /// The closed mesh of this building standing on `terrain`.
    pub fn mesh(&self, terrain: &ReferenceTerrain) -> MeshPart {
        let outline = self.outline();
        let (lo, hi) = ground_range(terrain, &outline);
        let z0 = lo - SINK;
        match &self.shape {
            Shape::Prism {
                outline,
                holes,
                height,
            } => prism(outline, holes, z0, hi + height),
            Shape::Podium {
                rect,
                height,
                towers,
            } => {
                let towers: Vec<(Rect, f64)> = towers.iter().map(|(r, h)| (*r, hi + h)).collect();
                podium_with_towers(*rect, z0, hi + height, &towers)
            }
            Shape::Pillars {
                rect,
                floor,
                height,
            } => {
                let pillars = pillars_under(*rect);
                slab_on_pillars(*rect, &pillars, z0, hi + floor, hi + height)
            }
            Shape::Gable {
                rect,
                eave,
                ridge,
                along_x,
            } => gable_house(*rect, z0, hi + eave, hi + ridge, *along_x),
        }
    }
}

/// Eight 0.8 m square pillars: two rows of four, 1 m in from the slab's edges.
fn pillars_under(r: Rect) -> Vec<Rect> {
    let size = 0.8;
    let xs: Vec<f64> = (0..4)
        .map(|k| r.x0 + 1.0 + (r.x1 - r.x0 - 2.0 - size) * k as f64 / 3.0)
        .collect();
    let ys = [r.y0 + 1.0, r.y1 - 1.0 - size];
    ys.iter()
        .flat_map(|&y| xs.iter().map(move |&x| Rect::at(x, y, size, size)))
        .collect()
}

fn ground_range(terrain: &ReferenceTerrain, ring: &[[f64; 2]]) -> (f64, f64) {
    let fold =
        |f: fn(f64, f64) -> f64, init: f64, k: usize| ring.iter().map(|p| p[k]).fold(init, f);
    let (x0, x1) = (
        fold(f64::min, f64::INFINITY, 0),
        fold(f64::max, f64::NEG_INFINITY, 0),
    );
    let (y0, y1) = (
        fold(f64::min, f64::INFINITY, 1),
        fold(f64::max, f64::NEG_INFINITY, 1),
    );
    terrain.range_over(x0, y0, x1, y1)
}

/// The buildings of `seed`, in id order (building id = index + 1).
pub fn plan_buildings(seed: u64) -> Vec<Plan> {
    let mut r = Rng::new(seed, 0xB111);
    let mut plans = Vec::new();
    let mut add = |kind: &str, shape: Shape| {
        let name = format!("building_{:02}_{kind}", plans.len() + 1);
        plans.push(Plan { name, shape });
    };
    // Shrinks a nominal size a little (anchored at its low corner: no new overlaps).
    let shrink = |r: &mut Rng, v: f64| v - r.range(0.0, 1.5);

    // South-west block.
    let (pw, pd) = (shrink(&mut r, 48.0), shrink(&mut r, 34.0));
    let (px, py) = (10.0, 10.0);
    add(
        "podium",
        Shape::Podium {
            rect: Rect::at(px, py, pw, pd),
            height: r.range(8.0, 12.0),
            towers: vec![
                (
                    Rect::at(px + 3.0, py + 3.0, 13.0, 13.0),
                    r.range(46.0, 56.0),
                ),
                (
                    Rect::at(px + 20.0, py + 5.0, 12.0, 10.0),
                    r.range(28.0, 40.0),
                ),
                (
                    Rect::at(px + 35.0, py + 14.0, 9.0, 13.0),
                    r.range(20.0, 30.0),
                ),
            ],
        },
    );
    let alley = r.range(2.0, 4.0);
    let wa = shrink(&mut r, 24.0);
    let depth = shrink(&mut r, 32.0);
    add(
        "box",
        Shape::Prism {
            outline: Rect::at(10.0, 52.0, wa, depth).ring(),
            holes: vec![],
            height: r.range(12.0, 20.0),
        },
    );
    add(
        "box",
        Shape::Prism {
            outline: Rect::at(10.0 + wa + alley, 52.0, shrink(&mut r, 22.0), depth).ring(),
            holes: vec![],
            height: r.range(9.0, 15.0),
        },
    );
    add(
        "tower",
        Shape::Prism {
            outline: Rect::at(66.0, 56.0, shrink(&mut r, 18.0), shrink(&mut r, 24.0)).ring(),
            holes: vec![],
            height: r.range(25.0, 35.0),
        },
    );

    // South-east block.
    let side = shrink(&mut r, 40.0);
    let court = r.range(14.0, 18.0);
    let c0 = (side - court) / 2.0;
    add(
        "courtyard",
        Shape::Prism {
            outline: Rect::at(112.0, 10.0, side, side).ring(),
            holes: vec![Rect::at(112.0 + c0, 10.0 + c0, court, court).ring()],
            height: r.range(14.0, 20.0),
        },
    );
    let (leg, arm) = (shrink(&mut r, 12.0), shrink(&mut r, 12.0));
    add(
        "l",
        Shape::Prism {
            outline: vec![
                [160.0, 10.0],
                [190.0, 10.0],
                [190.0, 10.0 + leg],
                [160.0 + arm, 10.0 + leg],
                [160.0 + arm, 44.0],
                [160.0, 44.0],
            ],
            holes: vec![],
            height: r.range(10.0, 16.0),
        },
    );
    let gap = r.range(2.5, 3.5);
    let mut x = 112.0;
    for k in 0..3 {
        let w = shrink(&mut r, 11.0);
        let eave = r.range(5.0, 7.0);
        add(
            "gable",
            Shape::Gable {
                rect: Rect::at(x, 64.0, w, 9.0),
                eave,
                ridge: eave + r.range(2.5, 4.0),
                along_x: true,
            },
        );
        x += w + if k == 0 { gap } else { 6.0 };
    }
    let eave = r.range(6.0, 8.0);
    add(
        "gable",
        Shape::Gable {
            rect: Rect::at(165.0, 60.0, shrink(&mut r, 20.0), 14.0),
            eave,
            ridge: eave + r.range(3.0, 5.0),
            along_x: false,
        },
    );

    // North-west block.
    let (uw, ud) = (shrink(&mut r, 40.0), shrink(&mut r, 30.0));
    let (notch_w, notch_d) = (r.range(12.0, 18.0), r.range(14.0, 20.0));
    let nx = 10.0 + (uw - notch_w) / 2.0;
    add(
        "u",
        Shape::Prism {
            outline: vec![
                [10.0, 112.0],
                [10.0 + uw, 112.0],
                [10.0 + uw, 112.0 + ud],
                [nx + notch_w, 112.0 + ud],
                [nx + notch_w, 112.0 + ud - notch_d],
                [nx, 112.0 + ud - notch_d],
                [nx, 112.0 + ud],
                [10.0, 112.0 + ud],
            ],
            holes: vec![],
            height: r.range(12.0, 18.0),
        },
    );
    let floor = r.range(3.8, 5.0);
    add(
        "pillars",
        Shape::Pillars {
            rect: Rect::at(58.0, 114.0, shrink(&mut r, 26.0), shrink(&mut r, 16.0)),
            floor,
            height: floor + r.range(8.0, 12.0),
        },
    );
    add(
        "tower",
        Shape::Prism {
            outline: Rect::at(60.0, 150.0, shrink(&mut r, 18.0), shrink(&mut r, 18.0)).ring(),
            holes: vec![],
            height: r.range(35.0, 50.0),
        },
    );
    add(
        "low",
        Shape::Prism {
            outline: Rect::at(12.0, 160.0, shrink(&mut r, 20.0), shrink(&mut r, 18.0)).ring(),
            holes: vec![],
            height: r.range(5.2, 7.0),
        },
    );

    // North-east block.
    let (leg, arm) = (shrink(&mut r, 12.0), shrink(&mut r, 12.0));
    add(
        "l",
        Shape::Prism {
            outline: vec![
                [160.0, 112.0],
                [192.0, 112.0],
                [192.0, 146.0],
                [192.0 - arm, 146.0],
                [192.0 - arm, 112.0 + leg],
                [160.0, 112.0 + leg],
            ],
            holes: vec![],
            height: r.range(18.0, 26.0),
        },
    );
    add(
        "box",
        Shape::Prism {
            outline: Rect::at(112.0, 116.0, shrink(&mut r, 28.0), shrink(&mut r, 22.0)).ring(),
            holes: vec![],
            height: r.range(20.0, 28.0),
        },
    );
    let alley = r.range(2.0, 3.5);
    let w = shrink(&mut r, 14.0);
    for x in [112.0, 112.0 + w + alley] {
        let eave = r.range(6.0, 8.0);
        add(
            "gable",
            Shape::Gable {
                rect: Rect::at(x, 150.0, w, 10.0),
                eave,
                ridge: eave + r.range(2.5, 4.0),
                along_x: false,
            },
        );
    }
    plans
}

/// Open areas (parks, squares) where free-standing trees grow.
pub const PARKS: [Rect; 3] = [
    Rect {
        x0: 64.0,
        y0: 8.0,
        x1: 88.0,
        y1: 48.0,
    },
    Rect {
        x0: 150.0,
        y0: 156.0,
        x1: 194.0,
        y1: 194.0,
    },
    Rect {
        x0: 40.0,
        y0: 176.0,
        x1: 88.0,
        y1: 194.0,
    },
];
