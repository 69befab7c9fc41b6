//! PLY mesh reader on small hand-written files.

use super::*;

const HEAD: &str = "ply\nformat ascii 1.0\ncomment two objects\nelement vertex 5\nproperty float x\nproperty float y\nproperty double z\nproperty uchar red\n";

fn ascii_two_objects() -> String {
    format!(
        "{HEAD}element face 3\nproperty list uchar int vertex_indices\nproperty int object\nproperty uchar class\nend_header\n\
         0 0 0 1\n10 0 0 1\n10 10 0 1\n0 10 0 1\n5 5 8 1\n4 0 1 2 3 0 2\n3 0 1 4 7 6\n3 1 2 4 7 6\n"
    )
}

#[test]
fn ascii_split_by_object_with_class() {
    let s = parse_ply_mesh(ascii_two_objects().as_bytes()).unwrap_or_default();
    let objects: Vec<(&str, ObjectKind, u32)> = s
        .objects
        .iter()
        .map(|o| (o.name.as_str(), o.kind, o.building))
        .collect();
    assert_eq!(
        objects,
        [
            ("object_0", ObjectKind::Ground, 0),
            ("object_7", ObjectKind::Building, 1)
        ]
    );
    assert_eq!(s.object_triangles(0).count(), 2);
    assert_eq!(s.object_triangles(1).count(), 2);
    assert_eq!(s.validate(), Ok(()));
}

fn binary_le(faces: &[&[i32]]) -> Vec<u8> {
    let mut b = format!(
        "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty double x\nproperty double y\nproperty double z\n\
         element face {}\nproperty list uchar uint vertex_indices\nelement extra 1\nproperty list int short stuff\nend_header\n",
        faces.len()
    )
    .into_bytes();
    for p in [
        [2_600_000.0, 1_200_000.0, 500.0],
        [2_600_010.0, 1_200_000.0, 500.0],
        [2_600_000.0, 1_200_010.0, 505.0f64],
    ] {
        for v in p {
            b.extend_from_slice(&v.to_le_bytes());
        }
    }
    for f in faces {
        b.push(f.len() as u8);
        for i in *f {
            b.extend_from_slice(&i.to_le_bytes());
        }
    }
    b.extend_from_slice(&2i32.to_le_bytes());
    b.extend_from_slice(&[1, 0, 2, 0]);
    b
}

#[test]
fn binary_without_labels_is_one_building_in_a_local_frame() {
    let s = parse_ply_mesh(&binary_le(&[&[0, 1, 2]])).unwrap_or_default();
    assert_eq!(s.objects.len(), 1);
    assert_eq!(
        (s.objects[0].kind, s.objects[0].building),
        (ObjectKind::Building, 1)
    );
    assert_eq!(s.origin, [2_600_000.0, 1_200_000.0, 0.0]);
    assert_eq!(s.vertices[1], [10.0, 0.0, 500.0]);
}

#[test]
fn errors() {
    let e = |d: &[u8]| parse_ply_mesh(d).err();
    assert_eq!(e(b"solid x\n"), Some(PlyMeshError::NotPly));
    assert_eq!(
        e(b"ply\nformat ascii 1.0\n"),
        Some(PlyMeshError::NoEndHeader)
    );
    assert!(matches!(
        e(b"ply\nformat ascii 1.0\nelement vertex 1\nproperty flt x\nend_header\n"),
        Some(PlyMeshError::Header {
            at: PlyPlace::Line(4),
            ..
        })
    ));
    assert_eq!(
        e(&binary_le(&[&[0, 1, 3]])),
        Some(PlyMeshError::FaceIndex {
            face: 0,
            index: 3,
            vertices: 3
        })
    );
    assert_eq!(
        e(&binary_le(&[&[0, 1]])),
        Some(PlyMeshError::ShortFace { face: 0, got: 2 })
    );
    let mut cut = binary_le(&[&[0, 1, 2]]);
    cut.truncate(cut.len() - 12);
    assert!(matches!(
        e(&cut),
        Some(PlyMeshError::Truncated {
            at: PlyPlace::Row { .. }
        })
    ));
    // ASCII errors carry the line: the 4th vertex row is line 17.
    let text = ascii_two_objects().replace("\n0 10 0 1\n", "\n0 ten 0 1\n");
    assert!(matches!(
        e(text.as_bytes()),
        Some(PlyMeshError::BadValue {
            at: PlyPlace::Line(17),
            ..
        })
    ));
    let no_faces = format!("{HEAD}end_header\n0 0 0 1\n1 0 0 1\n0 1 0 1\n0 0 1 1\n1 1 1 1\n");
    assert_eq!(e(no_faces.as_bytes()), Some(PlyMeshError::NoFaces));
    let no_list = "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty int a\nend_header\n1\n";
    assert!(matches!(
        e(no_list.as_bytes()),
        Some(PlyMeshError::MissingProperty { .. })
    ));
}

proptest::proptest! {
    #[test]
    fn random_bodies_never_panic(body in proptest::collection::vec(proptest::num::u8::ANY, 0..400), ascii in proptest::bool::ANY) {
        let format = if ascii { "ascii" } else { "binary_big_endian" };
        let mut data = format!(
            "ply\nformat {format} 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n\
             element face 2\nproperty list uchar int vertex_indices\nproperty short label\nend_header\n"
        )
        .into_bytes();
        data.extend_from_slice(&body);
        let _ = parse_ply_mesh(&data);
    }
}

#[test]
fn big_endian_face_lists_and_ascii_row_lengths_use_the_shared_readers() {
    let mut b = b"ply\nformat binary_big_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n\
                  element face 1\nproperty list uchar ushort vertex_indices\nproperty short label\nend_header\n"
        .to_vec();
    for v in [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0] {
        b.extend_from_slice(&v.to_be_bytes());
    }
    b.push(3);
    for i in [0u16, 1, 2] {
        b.extend_from_slice(&i.to_be_bytes());
    }
    b.extend_from_slice(&(-4i16).to_be_bytes());
    let s = parse_ply_mesh(&b).unwrap_or_default();
    let names: Vec<&str> = s.objects.iter().map(|o| o.name.as_str()).collect();
    assert_eq!(names, ["object_-4"]);
    assert_eq!(s.triangles.len(), 1);

    // An ASCII face row with an extra value is rejected on its line.
    let text = ascii_two_objects().replace("\n3 0 1 4 7 6\n", "\n3 0 1 4 7 6 9\n");
    assert!(matches!(
        parse_ply_mesh(text.as_bytes()),
        Err(PlyMeshError::RowLength {
            at: PlyPlace::Line(20),
            expected: 6,
            found: 7
        })
    ));
}
