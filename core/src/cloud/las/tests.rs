//! Tests of LAS/LAZ round trips, the building dimension, and the errors.

use std::io::Cursor;

use super::*;
use crate::cloud::Cloud;

fn sample_cloud() -> Cloud {
    Cloud {
        xyz: vec![[0.5, -1.25, 3.0], [100.001, 200.002, -5.5], [0.0, 0.0, 0.0]],
        intensity: Some(vec![0.0, 1234.0, 65535.0]),
        label: Some(vec![2, 6, 12]),
        building: Some(vec![0, 7, u32::MAX]),
        return_number: Some(vec![1, 2, 1]),
        number_of_returns: Some(vec![1, 3, 2]),
        origin: [637_000.0, 849_000.5, 100.0],
        crs: None,
    }
}

fn write(cloud: &Cloud, compressed: bool) -> Vec<u8> {
    write_las(Cursor::new(Vec::new()), cloud, compressed)
        .unwrap()
        .into_inner()
}

fn read(data: Vec<u8>) -> Result<Cloud, LasError> {
    read_las(Cursor::new(data))
}

fn assert_close(a: &Cloud, b: &Cloud) {
    assert_eq!(a.len(), b.len());
    assert_eq!(a.origin, b.origin);
    for (p, q) in a.xyz.iter().zip(&b.xyz) {
        for k in 0..3 {
            assert!((p[k] - q[k]).abs() <= 0.0005 + 1e-6, "{p:?} vs {q:?}");
        }
    }
    assert_eq!(a.label, b.label);
    assert_eq!(a.building, b.building);
    assert_eq!(a.intensity, b.intensity);
    assert_eq!(a.return_number, b.return_number);
    assert_eq!(a.number_of_returns, b.number_of_returns);
}

#[test]
fn las_and_laz_round_trip_with_building_ids() {
    let cloud = sample_cloud();
    for compressed in [false, true] {
        let back = read(write(&cloud, compressed)).unwrap();
        assert_close(&back, &cloud);
    }
}

#[test]
fn missing_attributes_come_back_as_zero_and_no_building() {
    let mut cloud = Cloud::from_xyz(vec![[1.0, 2.0, 3.0]]);
    cloud.origin = [0.0; 3];
    let back = read(write(&cloud, false)).unwrap();
    assert_eq!(back.xyz, cloud.xyz);
    assert_eq!(back.intensity, Some(vec![0.0]));
    assert_eq!(back.label, Some(vec![0]));
    assert_eq!(back.building, None);
    // A cloud without echoes is written as single returns.
    assert_eq!(back.return_number, Some(vec![1]));
    assert_eq!(back.number_of_returns, Some(vec![1]));
    let empty = read(write(&Cloud::default(), true)).unwrap();
    assert!(empty.is_empty());
}

#[test]
fn a_header_offset_far_from_the_data_is_replaced_by_the_floored_minimum() {
    // Written with origin 0 but coordinates 20 km out: the reader re-centres.
    let cloud = Cloud::from_xyz(vec![
        [20_000.25, 30_000.5, 10.0],
        [20_001.0, 30_001.0, 11.0],
    ]);
    let back = read(write(&cloud, false)).unwrap();
    assert_eq!(back.origin, [20_000.0, 30_000.0, 0.0]);
    assert_eq!(back.xyz[0], [0.25, 0.5, 10.0]);
}

/// Overwrites little-endian bytes of a written file.
fn patch(data: &mut [u8], at: usize, bytes: &[u8]) {
    data[at..at + bytes.len()].copy_from_slice(bytes);
}

#[test]
fn corrupt_headers_give_typed_errors() {
    let good = write(&sample_cloud(), false);

    let e = read(b"LASX this is not a las file, not at all, no".to_vec()).unwrap_err();
    assert!(matches!(e, LasError::Las(_)), "{e:?}");

    let mut cut = good.clone();
    cut.truncate(cut.len() - 40);
    let e = read(cut).unwrap_err();
    assert!(
        matches!(
            e,
            LasError::Truncated {
                count: 3,
                available: 1
            }
        ),
        "{e:?}"
    );

    let mut huge = good.clone();
    patch(&mut huge, 107, &0u32.to_le_bytes());
    patch(&mut huge, 247, &u64::MAX.to_le_bytes());
    let e = read(huge).unwrap_err();
    assert!(matches!(e, LasError::ImplausibleCount { .. }), "{e:?}");

    let mut evlr = good.clone();
    let len = evlr.len() as u64;
    patch(&mut evlr, 235, &(len - 10).to_le_bytes());
    patch(&mut evlr, 243, &1u32.to_le_bytes());
    let e = read(evlr).unwrap_err();
    assert!(matches!(e, LasError::BadEvlr { .. }), "{e:?}");

    let mut scaled = good.clone();
    patch(&mut scaled, 131, &1e300f64.to_le_bytes());
    let e = read(scaled).unwrap_err();
    assert!(
        matches!(e, LasError::BadCoordinate { axis: "x", .. }),
        "{e:?}"
    );

    let mut laz = write(&sample_cloud(), true);
    laz.truncate(laz.len() - 8);
    assert!(read(laz).is_err());
}

#[test]
fn a_chunk_table_counting_more_chunks_than_bytes_is_refused_before_it_is_allocated() {
    let mut laz = write(&sample_cloud(), true);
    let le = |at: usize, n: usize| -> u64 {
        laz[at..at + n]
            .iter()
            .rev()
            .fold(0u64, |v, &b| (v << 8) | u64::from(b))
    };
    // The point data starts with the chunk table's offset; the table starts
    // with its version and its count of chunks.
    let data_at = le(96, 4) as usize;
    let table_at = le(data_at, 8) as usize;
    assert!(
        table_at > data_at && table_at + 8 <= laz.len(),
        "{table_at}"
    );
    patch(&mut laz, table_at + 4, &u32::MAX.to_le_bytes());
    match read(laz) {
        Err(LasError::LazChunks(why)) => assert!(why.contains("4294967295 chunks"), "{why}"),
        other => panic!("unexpected {other:?}"),
    }
}

#[test]
fn truncated_laz_reports_the_point_index() {
    let cloud = Cloud::from_xyz(
        (0..5000)
            .map(|i| [i as f32, (i * 7 % 13) as f32, 0.5])
            .collect(),
    );
    let mut laz = write(&cloud, true);
    laz.truncate(laz.len() / 2);
    match read(laz) {
        Err(LasError::Points { count: 5000, .. } | LasError::Las(_) | LasError::Io(_)) => {}
        other => panic!("unexpected {other:?}"),
    }
}

#[test]
fn io_failures_are_io_errors() {
    struct Broken;
    impl std::io::Read for Broken {
        fn read(&mut self, _: &mut [u8]) -> std::io::Result<usize> {
            Err(std::io::Error::other("unplugged"))
        }
    }
    impl std::io::Seek for Broken {
        fn seek(&mut self, _: std::io::SeekFrom) -> std::io::Result<u64> {
            Err(std::io::Error::other("unplugged"))
        }
    }
    assert!(matches!(read_las(Broken), Err(LasError::Io(_))));
}

#[test]
fn unwritable_clouds_are_rejected() {
    let sink = || Cursor::new(Vec::new());
    let mut far = Cloud::from_xyz(vec![[3.0e6, 0.0, 0.0]]);
    assert!(matches!(
        write_las(sink(), &far, false),
        Err(LasError::CoordinateRange { axis: "x", .. })
    ));
    far.xyz[0] = [0.0; 3];
    far.intensity = Some(vec![70_000.0]);
    assert!(matches!(
        write_las(sink(), &far, false),
        Err(LasError::IntensityRange { index: 0, .. })
    ));
    far.intensity = Some(vec![]);
    assert!(matches!(
        write_las(sink(), &far, false),
        Err(LasError::InvalidCloud(_))
    ));
    far.intensity = None;
    far.origin = [f64::NAN, 0.0, 0.0];
    assert!(matches!(
        write_las(sink(), &far, false),
        Err(LasError::NonFiniteOrigin { .. })
    ));
}

/// A LAS 1.2 point format 3 file (GPS time and colour) of `n` points from
/// `x0` m east, with flags, scan angle, user data and flight line set, at
/// offset `offset`, scale 0.01.
fn producer_file(n: usize, x0: f64, offset: f64, compressed: bool) -> Vec<u8> {
    use ::las::point::{Classification, Format};
    use ::las::{Builder, Color, Point, Transform, Vector, Writer};
    let mut b = Builder::from((1, 2));
    b.point_format = Format::new(3).unwrap();
    b.point_format.is_compressed = compressed;
    let t = |o| Transform {
        scale: 0.01,
        offset: o,
    };
    b.transforms = Vector {
        x: t(offset),
        y: t(0.0),
        z: t(0.0),
    };
    let mut w = Writer::new(Cursor::new(Vec::new()), b.into_header().unwrap()).unwrap();
    for i in 0..n {
        w.write_point(Point {
            x: x0 + i as f64 * 0.37,
            y: 12.5 + i as f64,
            z: 3.25,
            intensity: 100 + i as u16,
            return_number: 1,
            number_of_returns: 2,
            classification: Classification::new(1).unwrap(),
            is_withheld: i % 2 == 0,
            is_key_point: i % 3 == 0,
            scan_angle: -12.0,
            user_data: 9,
            point_source_id: 707,
            gps_time: Some(306_234_562.25 + i as f64),
            color: Some(Color::new(10 * i as u16, 20, 30)),
            ..Default::default()
        })
        .unwrap();
    }
    w.into_inner().unwrap().into_inner()
}

fn points_of(data: Vec<u8>) -> (::las::Header, Vec<::las::point::Point>) {
    use ::las::Reader;
    let mut r = Reader::new(Cursor::new(data)).unwrap();
    let h = r.header().clone();
    let pts = r.read_all().unwrap().points().map(Result::unwrap).collect();
    (h, pts)
}

/// Relabelling with `labels`, returns of at most 2, no stated CRS.
fn how(labels: &[u8], compressed: bool) -> Relabel<'_> {
    Relabel {
        labels,
        max_return: 2,
        compressed,
        stated: None,
    }
}

#[test]
fn points_that_legacy_formats_cannot_hold_make_the_copy_las_1_4() {
    let src = producer_file(5, 1000.0, 1000.0, false);
    // Classes above 31 (format 3 has 5 bits), then returns above 5 (the
    // 1.2 header counts 5): each makes it LAS 1.4 format 7, nothing lost.
    for (labels, max_return) in [([40, 6, 2, 255, 1], 2), ([6; 5], 7)] {
        for compressed in [false, true] {
            let how = Relabel {
                max_return,
                ..how(&labels, compressed)
            };
            let out = relabel_las(
                vec![Cursor::new(src.clone())],
                Cursor::new(Vec::new()),
                &how,
            )
            .unwrap()
            .into_inner();
            let ((_, before), (h, after)) = (points_of(src.clone()), points_of(out));
            assert_eq!(h.version(), ::las::Version::new(1, 4));
            assert_eq!(h.point_format().to_u8().unwrap(), 7);
            for ((a, b), &c) in before.iter().zip(&after).zip(&labels) {
                assert_eq!(u8::from(b.classification), c);
                assert_eq!((b.x, b.y, b.z), (a.x, a.y, a.z));
                assert_eq!((b.gps_time, b.color), (a.gps_time, a.color));
                assert_eq!(b.intensity, a.intensity);
            }
        }
    }
}

#[test]
fn a_writer_that_cannot_close_is_an_error_not_a_panic() {
    // Return 7 in a LAS 1.2 header: the crate refuses it when closing,
    // which its `Drop` turns into a panic unless the writer is finished here.
    use ::las::{Builder, Point, Writer};
    let w = Writer::new(
        Cursor::new(Vec::new()),
        Builder::from((1, 2)).into_header().unwrap(),
    );
    let mut w = w.unwrap();
    let seven = Point {
        return_number: 7,
        number_of_returns: 7,
        ..Default::default()
    };
    w.write_point(seven).unwrap();
    let e = close::finish(w, Ok(())).unwrap_err();
    assert!(e.to_string().contains("return"), "{e}");
}

#[test]
fn relabelling_changes_the_class_and_nothing_else() {
    for compressed in [false, true] {
        let src = producer_file(5, 1000.0, 1000.0, false);
        let labels = [2, 6, 6, 5, 2];
        let out = relabel_las(
            vec![Cursor::new(src.clone())],
            Cursor::new(Vec::new()),
            &how(&labels, compressed),
        )
        .unwrap()
        .into_inner();
        let ((hi, before), (ho, after)) = (points_of(src), points_of(out));
        assert_eq!(ho.version(), hi.version());
        assert_eq!(ho.point_format().to_u8().unwrap(), 3);
        assert_eq!(ho.point_format().is_compressed, compressed);
        assert_eq!(ho.transforms(), hi.transforms());
        assert_eq!(ho.number_of_points(), 5);
        assert_eq!(ho.bounds(), hi.bounds());
        for ((a, b), &c) in before.iter().zip(&after).zip(&labels) {
            assert_eq!(u8::from(b.classification), c);
            let mut b = b.clone();
            b.classification = a.classification;
            assert_eq!(&b, a, "every other field stays");
        }
    }
}

#[test]
fn tiles_on_other_offsets_are_requantised_and_bad_classes_refused() {
    let a = producer_file(3, 1000.0, 1000.0, false);
    let b = producer_file(2, 1100.0, 1100.0, true);
    let sources = || vec![Cursor::new(a.clone()), Cursor::new(b.clone())];
    let out = relabel_las(sources(), Cursor::new(Vec::new()), &how(&[6; 5], true))
        .unwrap()
        .into_inner();
    let (h, pts) = points_of(out);
    assert_eq!(h.transforms().x.offset, 1000.0);
    let xs: Vec<f64> = pts.iter().map(|p| p.x).collect();
    let want = [1000.0, 1000.37, 1000.74, 1100.0, 1100.37];
    assert!(
        xs.iter().zip(want).all(|(x, w)| (x - w).abs() < 1e-6),
        "{xs:?}"
    );
    assert!(
        pts.iter()
            .all(|p| u8::from(p.classification) == 6 && p.gps_time.is_some())
    );
    let e = relabel_las(sources(), Cursor::new(Vec::new()), &how(&[6; 4], false)).unwrap_err();
    assert!(
        matches!(
            e,
            LasError::LabelCount {
                points: 5,
                labels: 4
            }
        ),
        "{e}"
    );
    let none: Vec<Cursor<Vec<u8>>> = Vec::new();
    let e = relabel_las(none, Cursor::new(Vec::new()), &how(&[], false)).unwrap_err();
    assert!(matches!(e, LasError::NoSource), "{e}");
}

#[test]
fn the_header_alone_gives_the_bounds_read_las_gives() {
    for compressed in [false, true] {
        let data = write(&sample_cloud(), compressed);
        let whole = read(data.clone()).unwrap();
        let corners = read_las_bounds(Cursor::new(data), UnreadableCrs::Fail)
            .unwrap()
            .expect("usable bounds");
        assert_eq!(corners.origin, whole.origin);
        let (lo, hi) = whole.bounds().unwrap();
        // Within the file's 1 mm grid (the header keeps f64, points f32).
        for (got, want) in corners.xyz.iter().zip([lo, hi]) {
            assert!(
                (0..3).all(|k| (got[k] - want[k]).abs() <= 1.5e-3),
                "{got:?} {want:?}"
            );
        }
        assert_eq!(corners.xyz.len(), 2);
    }
    // A header with unusable bounds (min above max) asks for a whole read.
    let mut data = write(&sample_cloud(), false);
    // Max X is at byte 179 of a LAS 1.4 header, min X at 187.
    data[179..187].copy_from_slice(&(-1.0e9f64).to_le_bytes());
    assert!(
        read_las_bounds(Cursor::new(data), UnreadableCrs::Fail)
            .unwrap()
            .is_none()
    );
}

#[test]
fn relabelling_a_file_without_a_crs_writes_the_stated_one_and_never_replaces_a_read_one() {
    use crate::crs::Crs;
    let rd = Crs::from_epsg(28992).unwrap();
    let src = producer_file(5, 1000.0, 1000.0, false);
    let stated = read_back_bytes(&src, &rd);
    let back = read_las(Cursor::new(stated.clone())).unwrap();
    let crs = back.crs.expect("the stated CRS is written");
    assert_eq!(crs.epsg, Some(28992));
    assert_eq!(crs.las_records[0].record_id, 34735, "LAS 1.2: GeoTIFF keys");
    // A file that states a CRS keeps its own records.
    let feet = Crs::from_epsg(2994).unwrap();
    let again = read_back_bytes(&stated, &feet);
    assert_eq!(
        read_las(Cursor::new(again))
            .unwrap()
            .crs
            .and_then(|c| c.epsg),
        Some(28992)
    );
}

/// `src` relabelled with `crs` stated for it, as bytes.
fn read_back_bytes(src: &[u8], crs: &crate::crs::Crs) -> Vec<u8> {
    let how = Relabel {
        stated: Some(crs),
        ..how(&[6; 5], false)
    };
    relabel_las(
        vec![Cursor::new(src.to_vec())],
        Cursor::new(Vec::new()),
        &how,
    )
    .unwrap()
    .into_inner()
}

/// Five points in a LAS 1.2 file with one `LASF_Projection` record.
fn file_with_projection(record_id: u16, data: Vec<u8>) -> Vec<u8> {
    use ::las::point::Format;
    use ::las::{Builder, Point, Vlr, Writer};
    let mut b = Builder::from((1, 2));
    b.point_format = Format::new(1).unwrap();
    b.vlrs.push(Vlr {
        user_id: crate::crs::LAS_PROJECTION.into(),
        record_id,
        description: "test".into(),
        data,
    });
    let mut w = Writer::new(Cursor::new(Vec::new()), b.into_header().unwrap()).unwrap();
    for i in 0..5 {
        w.write_point(Point {
            x: 1000.0 + f64::from(i),
            y: 2000.0,
            z: 3.0,
            gps_time: Some(0.0),
            ..Default::default()
        })
        .unwrap();
    }
    w.into_inner().unwrap().into_inner()
}

#[test]
fn crs_records_nobody_can_read_fail_or_are_skipped_and_a_stated_crs_replaces_them() {
    use crate::crs::{Crs, CrsError};
    let broken = file_with_projection(2112, b"PROJCS[\"x\",UNIT[\"m\",1]\0".to_vec());
    let e = read_las(Cursor::new(broken.clone())).unwrap_err();
    assert!(matches!(e, LasError::Crs(CrsError::Wkt(_))), "{e}");
    let skipped = read_las_with(Cursor::new(broken.clone()), UnreadableCrs::Skip).unwrap();
    assert_eq!((skipped.len(), skipped.crs.is_some()), (5, false));
    let corners = read_las_bounds(Cursor::new(broken.clone()), UnreadableCrs::Skip).unwrap();
    assert!(corners.is_some_and(|c| c.crs.is_none()));

    // Degrees stay an error: no stated CRS makes them lengths.
    // GeoKeyDirectory 1.1.0: model type geographic, EPSG:4326.
    let wgs84 = [1u16, 1, 0, 2, 1024, 0, 1, 2, 2048, 0, 1, 4326]
        .iter()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    let degrees = file_with_projection(34735, wgs84);
    let e = read_las_with(Cursor::new(degrees), UnreadableCrs::Skip).unwrap_err();
    assert!(
        matches!(e, LasError::Crs(CrsError::Geographic { .. })),
        "{e}"
    );

    // The copy carries the stated CRS, not beside the broken record.
    let rd = Crs::from_epsg(28992).unwrap();
    let copy = read_back_bytes(&broken, &rd);
    let (header, _) = points_of(copy.clone());
    let ids: Vec<u16> = header
        .all_vlrs()
        .filter(|v| v.user_id == crate::crs::LAS_PROJECTION)
        .map(|v| v.record_id)
        .collect();
    assert!(!ids.contains(&2112) && ids.contains(&34735), "{ids:?}");
    let back = read_las(Cursor::new(copy)).unwrap();
    assert_eq!(back.crs.and_then(|c| c.epsg), Some(28992));
}
