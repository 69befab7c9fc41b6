//! visualization_msgs helpers: polygons as LINE_STRIP markers and back
//! (how /target_regions carries `targets::Region`).

use skyground_core::targets::Region;
use skyground_msgs::builtin_interfaces::Time;
use skyground_msgs::geometry_msgs::{Point, Vector3};
use skyground_msgs::std_msgs::{ColorRGBA, Header};
use skyground_msgs::visualization_msgs::{Marker, MarkerArray};

use crate::runtime::Logger;

/// An opaque colour from 0..=1 components.
pub fn rgb(r: f32, g: f32, b: f32) -> ColorRGBA {
    ColorRGBA { r, g, b, a: 1.0 }
}

fn point(p: [f64; 3]) -> Point {
    Point {
        x: p[0],
        y: p[1],
        z: p[2],
    }
}

/// Where a marker goes and how it looks: header, namespace, id, colour.
#[derive(Debug, Clone)]
pub struct Look<'a> {
    /// Frame and stamp.
    pub header: &'a Header,
    /// Namespace.
    pub ns: String,
    /// Id within the namespace.
    pub id: i32,
    /// Colour.
    pub color: ColorRGBA,
}

impl Look<'_> {
    fn marker(&self, kind: i32, scale: [f64; 2], points: Vec<Point>) -> Marker {
        Marker {
            header: self.header.clone(),
            ns: self.ns.clone(),
            id: self.id,
            r#type: kind,
            action: Marker::ADD,
            scale: Vector3 {
                x: scale[0],
                y: scale[1],
                z: 0.0,
            },
            color: self.color,
            points,
            pose: identity_pose(),
            ..Marker::default()
        }
    }
}

/// A LINE_STRIP through `pts` (closed: back to the first point), `width` m wide.
pub fn line_strip(look: Look<'_>, pts: &[[f64; 3]], closed: bool, width: f64) -> Marker {
    let mut points: Vec<Point> = pts.iter().map(|&p| point(p)).collect();
    if closed && let Some(first) = points.first().cloned() {
        points.push(first);
    }
    look.marker(Marker::LINE_STRIP, [width, 0.0], points)
}

/// A LINE_LIST of segments.
pub fn line_list(look: Look<'_>, segments: &[[[f64; 3]; 2]], width: f64) -> Marker {
    let points = segments
        .iter()
        .flat_map(|s| [point(s[0]), point(s[1])])
        .collect();
    look.marker(Marker::LINE_LIST, [width, 0.0], points)
}

/// A POINTS marker, `size` m squares.
pub fn points(look: Look<'_>, pts: &[[f64; 3]], size: f64) -> Marker {
    let points = pts.iter().map(|&p| point(p)).collect();
    look.marker(Marker::POINTS, [size, size], points)
}

/// A DELETEALL marker: put first so a new array replaces the old one in RViz.
pub fn delete_all(header: &Header) -> Marker {
    Marker {
        header: header.clone(),
        action: Marker::DELETEALL,
        pose: identity_pose(),
        ..Marker::default()
    }
}

fn identity_pose() -> skyground_msgs::geometry_msgs::Pose {
    let mut p = skyground_msgs::geometry_msgs::Pose::default();
    p.orientation.w = 1.0;
    p
}

/// Regions as a MarkerArray: one closed LINE_STRIP per region, ns = the
/// building id, ids counting per building (docs/design.md /target_regions).
pub fn regions_to_markers(header: &Header, regions: &[Region]) -> MarkerArray {
    let mut markers = vec![delete_all(header)];
    let mut per_building = std::collections::BTreeMap::<u32, i32>::new();
    for r in regions {
        let id = per_building.entry(r.building).or_insert(0);
        let pts: Vec<[f64; 3]> = r
            .polygon
            .iter()
            .map(|p| [p[0], p[1], f64::from(r.z)])
            .collect();
        let look = Look {
            header,
            ns: r.building.to_string(),
            id: *id,
            color: rgb(1.0, 0.55, 0.0),
        };
        markers.push(line_strip(look, &pts, true, 0.3));
        *id += 1;
    }
    MarkerArray { markers }
}

/// Why a marker is not a region.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RegionMarkerError {
    /// The namespace is not a building id.
    #[error("marker ns `{0}` is not a building id (regions use the building id as ns)")]
    Namespace(String),
    /// Too few distinct points for a polygon.
    #[error("region marker {ns}/{id} has {points} points; a polygon needs at least 3")]
    TooFewPoints {
        /// Namespace.
        ns: String,
        /// Marker id.
        id: i32,
        /// Points given.
        points: usize,
    },
    /// A coordinate is NaN or infinite.
    #[error("region marker {ns}/{id} has a non-finite point")]
    NotFinite {
        /// Namespace.
        ns: String,
        /// Marker id.
        id: i32,
    },
}

/// The ADD LINE_STRIPs of `array`, each with its points as an xy ring
/// (closing point dropped; `None` when a point is not finite).
pub fn strips(array: &MarkerArray) -> impl Iterator<Item = (&Marker, Option<Vec<[f64; 2]>>)> {
    array
        .markers
        .iter()
        .filter(|m| m.action == Marker::ADD && m.r#type == Marker::LINE_STRIP)
        .map(|m| (m, strip_ring(m)))
}

fn strip_ring(m: &Marker) -> Option<Vec<[f64; 2]>> {
    if m.points
        .iter()
        .any(|p| !(p.x.is_finite() && p.y.is_finite() && p.z.is_finite()))
    {
        return None;
    }
    let mut ring: Vec<[f64; 2]> = m.points.iter().map(|p| [p.x, p.y]).collect();
    if ring.len() > 1 && ring.first() == ring.last() {
        ring.pop();
    }
    Some(ring)
}

/// The regions of a received MarkerArray and its first marker's stamp (a
/// set's DELETEALL carries the set's stamp); bad markers and unreadable
/// messages are logged, and the latter give `None`.
pub fn received_regions<I, E: std::fmt::Display>(
    log: &Logger,
    topic: &str,
    m: Result<(MarkerArray, I), E>,
) -> Option<(Vec<Region>, Time)> {
    match m {
        Ok((arr, _)) => {
            let (regions, errors) = markers_to_regions(&arr);
            for e in errors {
                log.warn(&format!("{topic}: {e}"));
            }
            let stamp = arr
                .markers
                .first()
                .map(|m| m.header.stamp)
                .unwrap_or_default();
            Some((regions, stamp))
        }
        Err(e) => {
            log.error(&format!("{topic}: unreadable message: {e}"));
            None
        }
    }
}

/// Regions back from a MarkerArray: every ADD LINE_STRIP becomes one region
/// (closing point dropped); DELETE/DELETEALL and other types are skipped.
/// Bad markers are returned as errors beside the good regions.
pub fn markers_to_regions(array: &MarkerArray) -> (Vec<Region>, Vec<RegionMarkerError>) {
    let mut regions = Vec::new();
    let mut errors = Vec::new();
    for (m, ring) in strips(array) {
        let Ok(building) = m.ns.parse::<u32>() else {
            errors.push(RegionMarkerError::Namespace(m.ns.clone()));
            continue;
        };
        let Some(polygon) = ring else {
            errors.push(RegionMarkerError::NotFinite {
                ns: m.ns.clone(),
                id: m.id,
            });
            continue;
        };
        if polygon.len() < 3 {
            errors.push(RegionMarkerError::TooFewPoints {
                ns: m.ns.clone(),
                id: m.id,
                points: polygon.len(),
            });
            continue;
        }
        let z = m.points.first().map_or(0.0, |p| p.z as f32);
        regions.push(Region {
            building,
            polygon,
            z,
        });
    }
    (regions, errors)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn regions_round_trip_through_markers() {
        let regions = vec![
            Region {
                building: 3,
                polygon: vec![[0.0, 0.0], [4.0, 0.0], [4.0, 3.0]],
                z: 1.5,
            },
            Region {
                building: 3,
                polygon: vec![[10.0, 0.0], [14.0, 0.0], [14.0, 3.0], [10.0, 3.0]],
                z: 2.0,
            },
            Region {
                building: 7,
                polygon: vec![[0.0, 9.0], [1.0, 9.0], [1.0, 10.0]],
                z: 0.0,
            },
        ];
        let arr = regions_to_markers(&Header::default(), &regions);
        assert_eq!(arr.markers[0].action, Marker::DELETEALL);
        assert_eq!(arr.markers[2].id, 1, "ids count per building");
        assert_eq!(arr.markers[1].points.len(), 4, "closed strip");
        let (back, errors) = markers_to_regions(&arr);
        assert!(errors.is_empty());
        assert_eq!(back, regions);
    }

    fn look<'a>(header: &'a Header, ns: &str, id: i32) -> Look<'a> {
        Look {
            header,
            ns: ns.into(),
            id,
            color: rgb(1.0, 0.0, 0.0),
        }
    }

    #[test]
    fn bad_region_markers_are_reported() {
        let h = Header::default();
        let mut arr = MarkerArray {
            markers: vec![
                line_strip(
                    look(&h, "roof", 0),
                    &[[0.0; 3], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0]],
                    true,
                    0.1,
                ),
                line_strip(look(&h, "2", 0), &[[0.0; 3], [1.0, 0.0, 0.0]], false, 0.1),
                line_strip(
                    look(&h, "2", 1),
                    &[[0.0; 3], [f64::NAN, 0.0, 0.0], [1.0, 1.0, 0.0]],
                    false,
                    0.1,
                ),
            ],
        };
        arr.markers.push(points(look(&h, "2", 5), &[[0.0; 3]], 0.1));
        let (back, errors) = markers_to_regions(&arr);
        assert!(back.is_empty());
        assert_eq!(errors.len(), 3);
        assert!(matches!(errors[0], RegionMarkerError::Namespace(_)));
        assert!(matches!(
            errors[1],
            RegionMarkerError::TooFewPoints { points: 2, .. }
        ));
        assert!(matches!(errors[2], RegionMarkerError::NotFinite { .. }));
    }
}
