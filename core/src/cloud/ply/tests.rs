//! Tests of the PLY reader and writer: round trips, skipping, and every error.

use super::*;
use proptest::prelude::*;

/// A file from header lines (without `ply`/`end_header`) and a body.
fn file(header: &str, body: &[u8]) -> Vec<u8> {
    let mut data = format!("ply\n{header}\nend_header\n").into_bytes();
    data.extend_from_slice(body);
    data
}

fn sample_cloud() -> Cloud {
    Cloud {
        xyz: vec![[1.5, -2.25, 3.0], [0.1, 0.2, 0.3], [-1e3, 4e3, 1e-3]],
        intensity: Some(vec![0.5, 1000.0, 65535.0]),
        label: Some(vec![2, 6, 255]),
        building: Some(vec![0, 7, u32::MAX]),
        return_number: None,
        number_of_returns: None,
        origin: [637_000.0, 849_000.5, -12.0],
        crs: None,
    }
}

fn err(data: &[u8]) -> PlyError {
    match parse_ply(data) {
        Ok(c) => panic!("expected an error, read {} points", c.len()),
        Err(e) => e,
    }
}

#[test]
fn round_trips_in_all_three_formats() {
    let cloud = sample_cloud();
    for format in [
        PlyFormat::Ascii,
        PlyFormat::BinaryLittleEndian,
        PlyFormat::BinaryBigEndian,
    ] {
        let mut data = Vec::new();
        write_ply_as(&mut data, &cloud, format).unwrap();
        assert_eq!(parse_ply(&data).unwrap(), cloud, "{format:?}");
        assert_eq!(read_ply(data.as_slice()).unwrap(), cloud, "{format:?}");
    }
}

#[test]
fn bare_cloud_round_trips_without_attributes_or_origin_comment() {
    let cloud = Cloud::from_xyz(vec![[1.0, 2.0, 3.0]]);
    let mut data = Vec::new();
    write_ply(&mut data, &cloud).unwrap();
    let text = String::from_utf8_lossy(&data);
    assert!(!text.contains("origin"), "{text}");
    assert!(!text.contains("intensity"), "{text}");
    assert_eq!(parse_ply(&data).unwrap(), cloud);
    let empty = Cloud::default();
    let mut data = Vec::new();
    write_ply(&mut data, &empty).unwrap();
    assert_eq!(parse_ply(&data).unwrap(), empty);
}

#[test]
fn face_elements_are_skipped_in_every_format() {
    let header = |f: &str| {
        format!(
            "format {f} 1.0\nelement face 2\nproperty list uchar int vertex_indices\n\
             property uchar flags\nelement vertex 2\nproperty double x\nproperty double y\n\
             property double z\nproperty list ushort float normals\n\
             element edge 1\nproperty int a\nproperty int b"
        )
    };
    let ascii = file(
        &header("ascii"),
        b"3 0 1 2 9\n\n4 0 1 2 3 8\n1 2 3 0\n4 5 6 2 0.5 0.25\n7 8\n",
    );
    let mut le = Vec::new();
    let mut be = Vec::new();
    for (out, big) in [(&mut le, false), (&mut be, true)] {
        let mut put = |le: &[u8], be: &[u8]| out.extend_from_slice(if big { be } else { le });
        // face rows: list of 3 then 4 ints, then flags
        for n in [3u8, 4] {
            put(&[n], &[n]);
            for i in 0..i32::from(n) {
                put(&i.to_le_bytes(), &i.to_be_bytes());
            }
            put(&[9], &[9]);
        }
        // vertex rows
        for (p, normals) in [([1.0f64, 2.0, 3.0], 0u16), ([4.0, 5.0, 6.0], 2)] {
            for v in p {
                put(&v.to_le_bytes(), &v.to_be_bytes());
            }
            put(&normals.to_le_bytes(), &normals.to_be_bytes());
            for k in 0..normals {
                let f = f32::from(k);
                put(&f.to_le_bytes(), &f.to_be_bytes());
            }
        }
        // edge row
        for v in [7i32, 8] {
            put(&v.to_le_bytes(), &v.to_be_bytes());
        }
    }
    let le = file(&header("binary_little_endian"), &le);
    let be = file(&header("binary_big_endian"), &be);
    let want = Cloud::from_xyz(vec![[1.0, 2.0, 3.0], [4.0, 5.0, 6.0]]);
    for data in [ascii, le, be] {
        assert_eq!(parse_ply(&data).unwrap(), want);
    }
}

#[test]
fn large_double_coordinates_get_a_whole_metre_origin() {
    let mut body = Vec::new();
    for v in [637_012.345f64, 849_321.5, 12.25, 637_013.0, 849_322.0, 13.0] {
        body.extend_from_slice(&v.to_le_bytes());
    }
    let data = file(
        "format binary_little_endian 1.0\nelement vertex 2\nproperty double x\n\
         property double y\nproperty double z",
        &body,
    );
    let c = parse_ply(&data).unwrap();
    assert_eq!(c.origin, [637_012.0, 849_321.0, 0.0]);
    assert!((c.xyz[0][0] - 0.345).abs() < 1e-6);
    assert_eq!(c.xyz[1], [1.0, 1.0, 13.0]);
}

#[test]
fn attributes_are_read_from_aliases_of_any_type() {
    let data = file(
        "format ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n\
         property float z\nproperty ushort scalar_Intensity\nproperty float scalar_classification\n\
         property int building_id\nproperty uchar label",
        b"0 0 0 100 6 3 9\n1 1 1 7 2.0 0 9\n",
    );
    let c = parse_ply(&data).unwrap();
    assert_eq!(c.intensity, Some(vec![100.0, 7.0]));
    assert_eq!(c.label, Some(vec![6, 2]));
    assert_eq!(c.building, Some(vec![3, 0]));
}

const XYZ: &str = "element vertex 1\nproperty float x\nproperty float y\nproperty float z";

fn msg(e: &PlyError) -> String {
    e.to_string()
}

#[test]
fn truncated_vertex_data_names_element_and_index() {
    let mut body = Vec::new();
    for i in 0..12 {
        for _ in 0..3 {
            body.extend_from_slice(&(i as f32).to_le_bytes());
        }
    }
    body.extend_from_slice(&[0; 5]);
    let header = "format binary_little_endian 1.0\nelement vertex 100\nproperty float x\n\
                  property float y\nproperty float z";
    let e = err(&file(header, &body));
    assert!(
        matches!(
            e,
            PlyError::Truncated {
                index: 12,
                count: 100,
                ..
            }
        ),
        "{e:?}"
    );
    assert_eq!(
        msg(&e),
        "truncated vertex data: element 'vertex' ends at index 12 of 100"
    );
}

#[test]
fn every_error_variant_is_reachable() {
    let le = "format binary_little_endian 1.0";
    let ascii = "format ascii 1.0";
    let one_float_vertex: Vec<u8> = [0f32; 3].iter().flat_map(|v| v.to_le_bytes()).collect();

    struct Failing;
    impl std::io::Read for Failing {
        fn read(&mut self, _: &mut [u8]) -> std::io::Result<usize> {
            Err(std::io::Error::other("disk on fire"))
        }
    }
    assert!(matches!(read_ply(Failing), Err(PlyError::Io(_))));
    assert!(matches!(err(b"PLY\n"), PlyError::BadMagic));
    assert!(matches!(err(b""), PlyError::BadMagic));
    assert!(matches!(
        err(b"ply\nformat ascii 1.0\n"),
        PlyError::MissingEndHeader
    ));
    assert!(matches!(err(&file(XYZ, b"")), PlyError::MissingFormat));
    assert!(matches!(
        err(&file("format text 1.0", b"")),
        PlyError::UnknownFormat { line: 2, .. }
    ));
    assert!(matches!(
        err(&file("format ascii 1.1", b"")),
        PlyError::UnsupportedVersion { line: 2, .. }
    ));
    assert!(matches!(
        err(&file("format ascii 1.0\nelement vertex many", b"")),
        PlyError::MalformedHeaderLine { line: 3, .. }
    ));
    assert!(matches!(
        err(&file(
            "format ascii 1.0\nelement vertex 1\nproperty quad x",
            b""
        )),
        PlyError::UnknownPropertyType { line: 4, .. }
    ));
    assert!(matches!(
        err(&file("format ascii 1.0\nelement face 0", b"")),
        PlyError::MissingVertexElement
    ));
    assert!(matches!(
        err(&file(
            "format ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y",
            b""
        )),
        PlyError::MissingCoordinate { axis: "z" }
    ));
    assert!(matches!(
        err(&file(
            "format ascii 1.0\nelement vertex 0\nproperty int x",
            b""
        )),
        PlyError::CoordinateType { axis: "x", .. }
    ));
    assert!(matches!(
        err(&file(
            "format ascii 1.0\nelement vertex 0\nproperty list uchar float y",
            b""
        )),
        PlyError::CoordinateType { axis: "y", .. }
    ));
    assert!(matches!(
        err(&file(
            &format!("{ascii}\n{XYZ}\nproperty list uchar uchar label"),
            b""
        )),
        PlyError::ListAttribute { .. }
    ));
    assert!(matches!(
        err(&file(
            &format!("{le}\n{XYZ}\nelement face 18446744073709551615\nproperty int a"),
            b""
        )),
        PlyError::CountOverflow { .. }
    ));
    assert!(matches!(
        err(&file(&format!("{le}\n{XYZ}"), &[0; 11])),
        PlyError::Truncated { index: 0, .. }
    ));
    assert!(matches!(
        err(&file(
            &format!("{ascii}\n{XYZ}\nelement f 1\nproperty list char int i"),
            b"0 0 0\n-1\n"
        )),
        PlyError::BadListLength { value: -1.0, .. }
    ));
    let e = err(&file(&format!("{ascii}\n{XYZ}"), b"0 zero 0\n"));
    assert!(
        matches!(e, PlyError::BadAsciiNumber { line: 8, .. }),
        "{e:?}"
    );
    assert!(
        msg(&e).contains("'zero' is not a valid float for property 'y'"),
        "{e}"
    );
    let e = err(&file(&format!("{ascii}\n{XYZ}"), b"0 0\n"));
    assert!(
        matches!(
            e,
            PlyError::AsciiRowLength {
                line: 8,
                expected: 3,
                found: 2,
                ..
            }
        ),
        "{e:?}"
    );
    let e = err(&file(&format!("{ascii}\n{XYZ}"), b"\n0 0 0 0\n"));
    assert!(
        matches!(
            e,
            PlyError::AsciiRowLength {
                line: 9,
                expected: 3,
                found: 4,
                ..
            }
        ),
        "{e:?}"
    );
    assert!(matches!(
        err(&file(
            &format!("{ascii}\n{XYZ}\nproperty float label"),
            b"0 0 0 2.5\n"
        )),
        PlyError::AttributeRange { index: 0, .. }
    ));
    assert!(matches!(
        err(&file(
            &format!("{ascii}\n{XYZ}\nproperty int building"),
            b"0 0 0 -3\n"
        )),
        PlyError::AttributeRange { .. }
    ));
    assert!(matches!(
        err(&file(&format!("{ascii}\n{XYZ}"), b"0 nan 0\n")),
        PlyError::BadCoordinate { axis: "y", .. }
    ));
    assert!(matches!(
        err(&file(
            &format!("{ascii}\ncomment skyground origin 0 nan 0\n{XYZ}"),
            b""
        )),
        PlyError::NonFiniteOrigin { .. }
    ));
    let mut bad_origin = Cloud::from_xyz(vec![]);
    bad_origin.origin[2] = f64::INFINITY;
    assert!(matches!(
        write_ply(Vec::new(), &bad_origin),
        Err(PlyError::NonFiniteOrigin { .. })
    ));
    let mut body = one_float_vertex.clone();
    body.push(0);
    assert!(matches!(
        err(&file(&format!("{le}\n{XYZ}"), &body)),
        PlyError::TrailingData { bytes: 1 }
    ));
    assert!(matches!(
        err(&file(&format!("{ascii}\n{XYZ}"), b"0 0 0\n1 1 1\n")),
        PlyError::TrailingData { bytes: 6 }
    ));
    let mut uneven = Cloud::from_xyz(vec![[0.0; 3]]);
    uneven.label = Some(vec![]);
    assert!(matches!(
        write_ply(Vec::new(), &uneven),
        Err(PlyError::InvalidCloud(_))
    ));
    // And the good file the broken ones were cut from:
    assert_eq!(
        parse_ply(&file(&format!("{le}\n{XYZ}"), &one_float_vertex))
            .unwrap()
            .len(),
        1
    );
}

#[test]
fn huge_counts_do_not_allocate_up_front() {
    for count in ["4000000000", "18446744073709551615"] {
        for format in ["ascii", "binary_big_endian"] {
            let header = format!(
                "format {format} 1.0\nelement vertex {count}\nproperty float x\n\
                 property float y\nproperty float z"
            );
            let e = err(&file(&header, b"0 0 0\n"));
            assert!(
                matches!(
                    e,
                    PlyError::Truncated { .. } | PlyError::CountOverflow { .. }
                ),
                "{e:?}"
            );
        }
    }
    let list = format!(
        "format binary_little_endian 1.0\n{XYZ}\nelement f 1\nproperty list uint double big"
    );
    let mut body: Vec<u8> = [0f32; 3].iter().flat_map(|v| v.to_le_bytes()).collect();
    body.extend_from_slice(&u32::MAX.to_le_bytes());
    assert!(matches!(
        err(&file(&list, &body)),
        PlyError::Truncated { .. }
    ));
}

#[test]
fn zero_property_elements_with_huge_counts_are_free() {
    let header = format!("format ascii 1.0\nelement nothing 18446744073709551615\n{XYZ}");
    assert_eq!(parse_ply(&file(&header, b"1 2 3\n")).unwrap().len(), 1);
}

#[test]
fn huge_headers_parse_in_linear_time() {
    let mut header = format!("format binary_little_endian 1.0\n{XYZ}");
    for i in 0..50_000 {
        header.push_str(&format!("\nproperty uchar p{i}"));
    }
    for i in 0..20_000 {
        header.push_str(&format!("\nelement e{i} 0"));
    }
    let mut body: Vec<u8> = [0f32; 3].iter().flat_map(|v| v.to_le_bytes()).collect();
    body.extend_from_slice(&[0; 50_000]);
    assert_eq!(parse_ply(&file(&header, &body)).unwrap().len(), 1);
}

proptest! {
    #[test]
    fn arbitrary_bytes_never_panic(data in proptest::collection::vec(any::<u8>(), 0..512)) {
        let _ = parse_ply(&data);
    }

    #[test]
    fn arbitrary_bodies_never_panic(
        format in prop::sample::select(vec!["ascii", "binary_little_endian", "binary_big_endian"]),
        body in proptest::collection::vec(any::<u8>(), 0..256),
    ) {
        let header = format!(
            "format {format} 1.0\nelement face 2\nproperty list uchar int i\n{XYZ}\n\
             property uchar label\nproperty list char double extra"
        );
        let _ = parse_ply(&file(&header, &body));
    }

    #[test]
    fn mutated_valid_files_never_panic(
        flips in proptest::collection::vec((any::<prop::sample::Index>(), any::<u8>()), 1..8),
        cut in any::<prop::sample::Index>(),
    ) {
        let mut data = Vec::new();
        write_ply(&mut data, &sample_cloud()).unwrap();
        for (at, byte) in flips {
            let i = at.index(data.len());
            data[i] = byte;
        }
        data.truncate(cut.index(data.len() + 1));
        let _ = parse_ply(&data);
    }
}
