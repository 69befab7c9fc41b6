//! `Cloud` → `PointCloud2` in one fixed, documented little-endian layout.

use skyground_core::cloud::Cloud;

use skyground_msgs::sensor_msgs::{PointCloud2, PointField};
use skyground_msgs::std_msgs::Header;

/// Choices for [`encode`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct EncodeOptions {
    /// Write x, y, z as FLOAT64 instead of FLOAT32.
    pub double: bool,
}

/// Byte offsets of the fields of one encoded point.
struct Layout {
    /// Size of one coordinate: 4 (FLOAT32) or 8 (FLOAT64).
    coordinate: usize,
    /// Offset of `intensity`, when written.
    intensity: Option<usize>,
    /// Offset of `building`, when written.
    building: Option<usize>,
    /// Offsets of the extra FLOAT32 columns, in their order.
    extra: Vec<usize>,
    /// Offset of `label`, when written.
    label: Option<usize>,
    /// Offsets of `return_number` and `number_of_returns`, when written.
    echo: Option<(usize, usize)>,
    /// Bytes per point, padded.
    point_step: usize,
}

impl Layout {
    /// Widest fields first so that no field needs inner padding; the record is
    /// padded to the coordinate size so every point starts aligned.
    fn of(cloud: &Cloud, extra: usize, opts: &EncodeOptions) -> Self {
        let coordinate = if opts.double { 8 } else { 4 };
        let mut end = 3 * coordinate;
        let mut place = |present: bool, size: usize| {
            present.then(|| {
                let offset = end;
                end += size;
                offset
            })
        };
        let intensity = place(cloud.intensity.is_some(), 4);
        let building = place(cloud.building.is_some(), 4);
        let extra = (0..extra).filter_map(|_| place(true, 4)).collect();
        let label = place(cloud.label.is_some(), 1);
        let has_echo = cloud.return_number.is_some() && cloud.number_of_returns.is_some();
        let echo = place(has_echo, 1).zip(place(has_echo, 1));
        Self {
            coordinate,
            intensity,
            building,
            extra,
            label,
            echo,
            point_step: end.next_multiple_of(coordinate),
        }
    }

    /// The `PointField` list, in offset order.
    fn fields(&self, extra: &[(&str, &[f32])]) -> Vec<PointField> {
        let coordinate_type = if self.coordinate == 8 {
            PointField::FLOAT64
        } else {
            PointField::FLOAT32
        };
        let field = |name: &str, offset: usize, datatype: u8| {
            PointField::single(name, offset as u32, datatype)
        };
        let mut fields = vec![
            field("x", 0, coordinate_type),
            field("y", self.coordinate, coordinate_type),
            field("z", 2 * self.coordinate, coordinate_type),
        ];
        fields.extend(
            self.intensity
                .map(|o| field("intensity", o, PointField::FLOAT32)),
        );
        fields.extend(
            self.building
                .map(|o| field("building", o, PointField::UINT32)),
        );
        for (&o, (name, _)) in self.extra.iter().zip(extra) {
            fields.push(field(name, o, PointField::FLOAT32));
        }
        fields.extend(self.label.map(|o| field("label", o, PointField::UINT8)));
        if let Some((rn, nr)) = self.echo {
            fields.push(field("return_number", rn, PointField::UINT8));
            fields.push(field("number_of_returns", nr, PointField::UINT8));
        }
        fields
    }
}

/// Encodes a cloud as an unorganized (height 1), little-endian, dense `PointCloud2`.
///
/// Layout of one point (offsets in bytes; FLOAT64 coordinates in brackets):
///
/// | field     | type    | offset   | when                  |
/// |-----------|---------|----------|-----------------------|
/// | x, y, z   | FLOAT32 [FLOAT64] | 0, 4, 8 [0, 8, 16] | always |
/// | intensity | FLOAT32 | next     | `cloud.intensity` set |
/// | building  | UINT32  | next     | `cloud.building` set  |
/// | label     | UINT8   | next     | `cloud.label` set     |
/// | return_number, number_of_returns | UINT8 | next | both echo columns set |
///
/// Fields follow each other without gaps (widest first, so each is aligned)
/// and `point_step` is rounded up to a multiple of 4 [8]; the padding bytes
/// are zero. E.g. x y z intensity label: `point_step` 20; with building too: 24.
/// `cloud.origin` is not written (PointCloud2 has no place for it).
///
/// An attribute column shorter than the cloud (a cloud failing
/// [`Cloud::validate`]) is padded with zeros. A PointCloud2 row holds at most
/// `u32::MAX` bytes, so points beyond that (over 178 M points at 24 bytes
/// each) are left out; `width` always equals the points written.
pub fn encode(cloud: &Cloud, header: Header, opts: &EncodeOptions) -> PointCloud2 {
    encode_with(cloud, &[], header, opts)
}

/// As [`encode`], with named extra FLOAT32 columns (e.g. `nx`, `ny`) placed
/// after `building`; a column shorter than the cloud is padded with zeros.
/// Standard `PointField`s: any PointCloud2 reader sees them, [`super::decode`]
/// returns them in [`super::Decoded::extra`].
pub fn encode_with(
    cloud: &Cloud,
    extra: &[(&str, &[f32])],
    header: Header,
    opts: &EncodeOptions,
) -> PointCloud2 {
    let layout = Layout::of(cloud, extra.len(), opts);
    let step = layout.point_step;
    let max_points = u32::MAX as usize / step;
    let n = cloud.len().min(max_points);
    let mut data = vec![0u8; n * step];
    let intensity = cloud.intensity.as_deref().unwrap_or_default();
    let building = cloud.building.as_deref().unwrap_or_default();
    let label = cloud.label.as_deref().unwrap_or_default();
    let rn = cloud.return_number.as_deref().unwrap_or_default();
    let nr = cloud.number_of_returns.as_deref().unwrap_or_default();
    for (i, (record, p)) in data.chunks_exact_mut(step).zip(&cloud.xyz).enumerate() {
        if opts.double {
            put(record, 0, &f64::from(p[0]).to_le_bytes());
            put(record, 8, &f64::from(p[1]).to_le_bytes());
            put(record, 16, &f64::from(p[2]).to_le_bytes());
        } else {
            put(record, 0, &p[0].to_le_bytes());
            put(record, 4, &p[1].to_le_bytes());
            put(record, 8, &p[2].to_le_bytes());
        }
        if let Some(o) = layout.intensity {
            let v = intensity.get(i).copied().unwrap_or_default();
            put(record, o, &v.to_le_bytes());
        }
        if let Some(o) = layout.building {
            let v = building.get(i).copied().unwrap_or_default();
            put(record, o, &v.to_le_bytes());
        }
        for (&o, (_, column)) in layout.extra.iter().zip(extra) {
            let v = column.get(i).copied().unwrap_or_default();
            put(record, o, &v.to_le_bytes());
        }
        if let Some(o) = layout.label {
            put(record, o, &[label.get(i).copied().unwrap_or_default()]);
        }
        if let Some((a, b)) = layout.echo {
            put(record, a, &[rn.get(i).copied().unwrap_or_default()]);
            put(record, b, &[nr.get(i).copied().unwrap_or_default()]);
        }
    }
    PointCloud2 {
        header,
        height: 1,
        width: n as u32,
        fields: layout.fields(extra),
        is_bigendian: false,
        point_step: step as u32,
        row_step: (n * step) as u32,
        data,
        is_dense: true,
    }
}

/// Copies `bytes` into `record` at `offset` (the layout guarantees the fit).
#[inline(always)]
fn put<const N: usize>(record: &mut [u8], offset: usize, bytes: &[u8; N]) {
    if let Some(slot) = record.get_mut(offset..offset + N) {
        slot.copy_from_slice(bytes);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn offsets(msg: &PointCloud2) -> Vec<(String, u32, u8)> {
        msg.fields
            .iter()
            .map(|f| (f.name.clone(), f.offset, f.datatype))
            .collect()
    }

    #[test]
    fn xyz_only_is_twelve_bytes_per_point() {
        let cloud = Cloud::from_xyz(vec![[1.0, 2.0, 3.0], [4.0, 5.0, 6.0]]);
        let msg = encode(&cloud, Header::default(), &EncodeOptions::default());
        assert_eq!(
            (msg.height, msg.width, msg.point_step, msg.row_step),
            (1, 2, 12, 24)
        );
        assert!(msg.is_dense && !msg.is_bigendian);
        assert_eq!(&msg.data[12..16], &4.0f32.to_le_bytes());
        assert_eq!(
            offsets(&msg),
            [("x".into(), 0, 7), ("y".into(), 4, 7), ("z".into(), 8, 7)]
        );
    }

    #[test]
    fn extra_columns_follow_building_as_float32() {
        let mut cloud = Cloud::from_xyz(vec![[1.0, 2.0, 3.0], [4.0, 5.0, 6.0]]);
        cloud.building = Some(vec![7, 8]);
        cloud.label = Some(vec![6, 6]);
        let nx = [0.5f32, -0.25];
        let msg = encode_with(
            &cloud,
            &[("nx", &nx), ("ny", &[1.0])],
            Header::default(),
            &EncodeOptions::default(),
        );
        assert_eq!(
            offsets(&msg)[3..],
            [
                ("building".into(), 12, 6),
                ("nx".into(), 16, 7),
                ("ny".into(), 20, 7),
                ("label".into(), 24, 2),
            ]
        );
        assert_eq!(msg.point_step, 28);
        assert_eq!(&msg.data[28 + 16..28 + 20], &(-0.25f32).to_le_bytes());
        // The short column is padded with zeros.
        assert_eq!(&msg.data[28 + 20..28 + 24], &0.0f32.to_le_bytes());
        let d = super::super::decode(&msg).expect("decodes");
        assert_eq!(d.cloud, cloud);
        assert_eq!(d.column("nx"), Some(&nx[..]));
        assert_eq!(d.column("ny"), Some(&[1.0, 0.0][..]));
        assert_eq!(d.column("nz"), None);
        // Through tiles too (how big clouds travel).
        let mut joiner = super::super::tiles::Assembler::new(1);
        let whole = super::super::tiles::split(msg.clone(), 1)
            .into_iter()
            .find_map(|t| joiner.push(t))
            .expect("joined");
        assert_eq!(super::super::decode(&whole).map(|d| d.extra), Ok(d.extra));
    }

    #[test]
    fn all_attributes_layout() {
        let mut cloud = Cloud::from_xyz(vec![[1.0, 2.0, 3.0]]);
        cloud.intensity = Some(vec![0.5]);
        cloud.label = Some(vec![6]);
        cloud.building = Some(vec![0x0102_0304]);
        let msg = encode(&cloud, Header::default(), &EncodeOptions::default());
        assert_eq!(
            offsets(&msg),
            [
                ("x".into(), 0, 7),
                ("y".into(), 4, 7),
                ("z".into(), 8, 7),
                ("intensity".into(), 12, 7),
                ("building".into(), 16, 6),
                ("label".into(), 20, 2),
            ]
        );
        assert_eq!(msg.point_step, 24);
        assert_eq!(&msg.data[16..24], &[4, 3, 2, 1, 6, 0, 0, 0]);
    }

    #[test]
    fn double_layout_pads_to_eight() {
        let mut cloud = Cloud::from_xyz(vec![[1.0, 2.0, 3.0]]);
        cloud.label = Some(vec![2]);
        let msg = encode(&cloud, Header::default(), &EncodeOptions { double: true });
        assert_eq!(msg.point_step, 32);
        assert_eq!(&msg.data[8..16], &2.0f64.to_le_bytes());
        assert_eq!(msg.data[24], 2);
        assert_eq!(msg.fields[0].datatype, PointField::FLOAT64);
    }

    #[test]
    fn short_attribute_column_is_zero_filled() {
        let mut cloud = Cloud::from_xyz(vec![[0.0; 3]; 2]);
        cloud.label = Some(vec![9]);
        let msg = encode(&cloud, Header::default(), &EncodeOptions::default());
        assert_eq!((msg.data[12], msg.data[28]), (9, 0));
    }
}
