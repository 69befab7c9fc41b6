//! Tiling: how skyground sends a cloud too large for one DDS sample.
//!
//! RustDDS sends a sample's fragments in one burst, and a receiver whose socket
//! buffer is smaller than the sample loses it (see docs/transport.md). So a
//! cloud of `n` points goes out as consecutive PointCloud2 messages on the same
//! topic, each a complete, valid cloud of its own:
//!
//! - every tile has the same `header` (stamp and frame_id), fields and layout;
//! - every tile but the last holds exactly `tile_points` points, the last holds
//!   `n % tile_points` (possibly 0), so a tile with fewer than `tile_points`
//!   points ends its cloud, and a cloud smaller than one tile is one message.
//!
//! A receiver that knows `tile_points` concatenates tiles with the same stamp
//! until a short tile arrives ([`Assembler`]); one that does not simply sees
//! several smaller clouds, each correct.

use std::collections::VecDeque;

use skyground_msgs::builtin_interfaces::Time;
use skyground_msgs::sensor_msgs::PointCloud2;

/// Default tile size: 65,536 points (1 MiB at 16 bytes per point).
pub const DEFAULT_TILE_POINTS: u32 = 65_536;

/// Splits an unorganized (height 1) cloud into tiles per the module rule.
/// Organized clouds (height > 1) and clouds smaller than a tile are returned whole.
pub fn split(msg: PointCloud2, tile_points: u32) -> Vec<PointCloud2> {
    let tile_points = tile_points.max(1);
    if msg.height != 1 || msg.width < tile_points {
        return vec![msg];
    }
    let step = msg.point_step as usize;
    let tile_bytes = tile_points as usize * step;
    let used = (msg.width as usize)
        .saturating_mul(step)
        .min(msg.data.len());
    let full = msg.width / tile_points;
    let mut out = Vec::with_capacity(full as usize + 1);
    for k in 0..=full {
        let width = if k < full {
            tile_points
        } else {
            msg.width % tile_points
        };
        let start = (k as usize * tile_bytes).min(used);
        let end = (start + width as usize * step).min(used);
        out.push(PointCloud2 {
            header: msg.header.clone(),
            height: 1,
            width,
            fields: msg.fields.clone(),
            is_bigendian: msg.is_bigendian,
            point_step: msg.point_step,
            row_step: width * msg.point_step,
            data: msg
                .data
                .get(start..end)
                .map(<[u8]>::to_vec)
                .unwrap_or_default(),
            is_dense: msg.is_dense,
        });
    }
    out
}

/// Number of messages [`split`] makes of a cloud of `width` points.
pub fn tile_count(width: u32, tile_points: u32) -> u32 {
    width / tile_points.max(1) + 1
}

/// Reassembles tiled clouds arriving in order on one topic.
///
/// Tiles are grouped by `header.stamp`; a group completes at its first short
/// tile. A group still open when a tile with a newer stamp arrives is given up
/// (its cloud was superseded, e.g. a late joiner saw only the tail of an old
/// cloud) and counted in [`Assembler::abandoned`]. Tiles that disagree with
/// their group's layout start the group afresh.
#[derive(Debug)]
pub struct Assembler {
    tile_points: u32,
    open: VecDeque<PointCloud2>,
    max_open: usize,
    abandoned: usize,
}

impl Assembler {
    /// An assembler for tiles of `tile_points` points.
    pub fn new(tile_points: u32) -> Self {
        Self {
            tile_points: tile_points.max(1),
            open: VecDeque::new(),
            max_open: 2,
            abandoned: 0,
        }
    }

    /// Number of partial clouds given up so far.
    pub fn abandoned(&self) -> usize {
        self.abandoned
    }

    /// Feeds one message; returns the whole cloud when this message completes one.
    pub fn push(&mut self, tile: PointCloud2) -> Option<PointCloud2> {
        let stamp = tile.header.stamp;
        let pos = self
            .open
            .iter()
            .position(|g| same_stamp(&g.header.stamp, &stamp));
        let complete = tile.height != 1 || tile.width != self.tile_points;
        let group = match pos {
            Some(i) => {
                let mut g = self.open.remove(i)?;
                if compatible(&g, &tile) {
                    g.width = g.width.saturating_add(tile.width);
                    g.row_step = g.width.saturating_mul(g.point_step);
                    g.data.extend_from_slice(&tile.data);
                    g.is_dense &= tile.is_dense;
                    g
                } else {
                    self.abandoned += 1;
                    tile
                }
            }
            None => tile,
        };
        if complete {
            // Older open groups can no longer complete in order.
            let before = self.open.len();
            self.open.retain(|g| newer(&g.header.stamp, &stamp));
            self.abandoned += before - self.open.len();
            return Some(group);
        }
        self.open.push_back(group);
        while self.open.len() > self.max_open {
            self.open.pop_front();
            self.abandoned += 1;
        }
        None
    }
}

fn same_stamp(a: &Time, b: &Time) -> bool {
    a.sec == b.sec && a.nanosec == b.nanosec
}

fn newer(a: &Time, b: &Time) -> bool {
    (a.sec, a.nanosec) > (b.sec, b.nanosec)
}

fn compatible(g: &PointCloud2, t: &PointCloud2) -> bool {
    g.fields == t.fields
        && g.point_step == t.point_step
        && g.is_bigendian == t.is_bigendian
        && g.header.frame_id == t.header.frame_id
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::convert::pointcloud2::{EncodeOptions, decode, encode};
    use skyground_core::cloud::Cloud;
    use skyground_msgs::std_msgs::Header;

    fn cloud(n: usize, sec: i32) -> PointCloud2 {
        let mut c = Cloud::from_xyz((0..n).map(|i| [i as f32, 0.0, 1.0]).collect());
        c.label = Some((0..n).map(|i| (i % 7) as u8).collect());
        let header = Header {
            stamp: Time { sec, nanosec: 5 },
            frame_id: "map".into(),
        };
        encode(&c, header, &EncodeOptions::default())
    }

    #[test]
    fn split_follows_the_rule() {
        let tiles = split(cloud(10, 1), 4);
        assert_eq!(
            tiles.iter().map(|t| t.width).collect::<Vec<_>>(),
            vec![4, 4, 2]
        );
        let tiles = split(cloud(8, 1), 4);
        assert_eq!(
            tiles.iter().map(|t| t.width).collect::<Vec<_>>(),
            vec![4, 4, 0]
        );
        assert_eq!(tile_count(8, 4), 3);
        assert_eq!(split(cloud(3, 1), 4).len(), 1);
        for t in split(cloud(10, 1), 4) {
            assert!(decode(&t).is_ok(), "every tile is a valid cloud");
        }
    }

    #[test]
    fn assembler_restores_the_cloud() {
        for n in [0, 3, 4, 8, 10, 33] {
            let whole = cloud(n, 2);
            let mut a = Assembler::new(4);
            let mut out = Vec::new();
            for t in split(whole.clone(), 4) {
                out.extend(a.push(t));
            }
            assert_eq!(out, vec![whole], "n = {n}");
        }
    }

    #[test]
    fn superseded_partial_cloud_is_abandoned() {
        let mut a = Assembler::new(4);
        let old = split(cloud(10, 1), 4);
        assert!(a.push(old[1].clone()).is_none());
        let new = cloud(6, 2);
        let mut out = Vec::new();
        for t in split(new.clone(), 4) {
            out.extend(a.push(t));
        }
        assert_eq!(out, vec![new]);
        assert_eq!(a.abandoned(), 1);
    }

    #[test]
    fn a_foreign_single_message_passes_through() {
        let mut a = Assembler::new(4);
        let m = cloud(1000, 3);
        assert_eq!(a.push(m.clone()), Some(m));
    }
}
