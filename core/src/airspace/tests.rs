//! The airspace over a 10 m cube standing on open ground.

use geo::{MultiPolygon, polygon};

use super::*;
use crate::cloud::Cloud;
use crate::geom::fixtures::cube_prior;

fn airspace() -> Airspace {
    Airspace::from_prior(
        &cube_prior(),
        AirspaceRules::default(),
        0.6,
        [5.0, 5.0, 0.7],
    )
    .unwrap()
}

#[test]
fn facades_and_roofs_keep_their_distance_and_open_air_is_free() {
    let a = airspace();
    a.check([26.0, 34.0, 5.0])
        .expect("4 m beside the north wall");
    a.check([25.0, 25.0, 13.5]).expect("3.5 m over the roof");
    a.check([45.0, 45.0, 3.0]).expect("3 m over open ground");
    let Err(Violation::TooClose {
        what,
        distance_m,
        required_m,
        ..
    }) = a.check([25.0, 32.0, 5.0])
    else {
        panic!("2 m beside a wall must be refused");
    };
    assert_eq!(what, Obstacle::Building);
    assert!(
        (distance_m - 2.0).abs() < 0.3 && required_m == 3.0,
        "{distance_m} {required_m}"
    );
    assert!(matches!(
        a.check([25.0, 25.0, 12.0]),
        Err(Violation::TooClose {
            what: Obstacle::Building,
            ..
        })
    ));
    let Err(Violation::TooClose {
        what, required_m, ..
    }) = a.check([45.0, 45.0, 2.0])
    else {
        panic!("2 m over the ground must be refused");
    };
    assert_eq!(what, Obstacle::Other);
    assert!(
        (required_m - 2.6).abs() < 1e-6,
        "body 0.6 + margin 2: {required_m}"
    );
}

#[test]
fn the_ceiling_the_fence_and_the_prior_s_extent_refuse_with_the_reason() {
    let fence: MultiPolygon<f64> =
        polygon![(x: 0.0, y: 0.0), (x: 40.0, y: 0.0), (x: 40.0, y: 40.0), (x: 0.0, y: 40.0)].into();
    let a = airspace().with_fence(fence);
    let e = a.check([10.0, 10.0, 121.0]).unwrap_err();
    assert!(matches!(e, Violation::AboveCeiling { .. }), "{e}");
    assert!(e.to_string().contains("120 m ceiling"), "{e}");
    assert!(matches!(
        a.check([50.0, 10.0, 20.0]),
        Err(Violation::OutsideFence { .. })
    ));
    assert!(matches!(
        a.check([70.0, 10.0, 20.0]),
        Err(Violation::Unmapped { .. })
    ));
    // A plan: up from the pad, across inside the fence, then out of it.
    let path = [
        [5.0, 5.0, 0.7],
        [5.0, 5.0, 20.0],
        [35.0, 5.0, 20.0],
        [50.0, 5.0, 20.0],
    ];
    let r = a.check_path(&path).unwrap_err();
    assert_eq!(r.leg, 3, "{r}");
    assert!(r.to_string().contains("geofence"), "{r}");
    a.check_path(&path[..3])
        .expect("take-off from the pad and a leg inside");
}

#[test]
fn a_leg_through_a_building_is_refused_though_both_ends_are_free() {
    let a = airspace();
    let path = [[15.0, 25.0, 5.0], [35.0, 25.0, 5.0]];
    for p in path {
        a.check(p).expect("each end is 5 m from the walls");
    }
    let r = a.check_path(&path).unwrap_err();
    assert_eq!(r.leg, 1);
    assert!(
        matches!(
            r.violation,
            Violation::TooClose {
                what: Obstacle::Building,
                ..
            }
        ),
        "{r}"
    );
}

#[test]
fn an_empty_prior_and_bad_rules_are_refused() {
    let e = Airspace::from_prior(
        &Cloud::from_xyz(vec![]),
        AirspaceRules::default(),
        0.6,
        [0.0; 3],
    );
    assert!(matches!(e, Err(AirspaceError::EmptyPrior)));
    let rules = AirspaceRules {
        cell_m: 0.0,
        ..AirspaceRules::default()
    };
    let e = Airspace::from_prior(&cube_prior(), rules, 0.6, [0.0; 3]).unwrap_err();
    assert!(e.to_string().contains("cell_m"), "{e}");
}

#[test]
fn cells_the_survey_left_empty_are_filled_from_their_highest_neighbours() {
    // A hole of 2 × 2 cells in the roof (a dark skylight gives no return).
    let mut prior = cube_prior();
    let keep: Vec<bool> = prior
        .xyz
        .iter()
        .map(|p| !((24.0..25.0).contains(&p[0]) && (24.0..25.0).contains(&p[1])))
        .collect();
    let mut k = keep.iter();
    prior.xyz.retain(|_| *k.next().unwrap());
    let mut k = keep.iter();
    prior.label.as_mut().unwrap().retain(|_| *k.next().unwrap());
    let a = Airspace::from_prior(&prior, AirspaceRules::default(), 0.6, [5.0, 5.0, 0.7]).unwrap();
    assert!(
        a.check([24.5, 24.5, 11.0]).is_err(),
        "the hole is not a way into the building"
    );
}

#[test]
fn the_grown_floor_answers_as_the_search_over_the_neighbours_does() {
    let a = airspace();
    let mut rng = crate::rng::Rng::keyed(7, 0);
    let mut refused = 0;
    for _ in 0..20_000 {
        let p = [
            (rng.unit() * 59.0 + 0.5) as f32,
            (rng.unit() * 59.0 + 0.5) as f32,
            (rng.unit() * 16.0) as f32,
        ];
        let by_floor = a.check(p).is_ok();
        let by_search = a.too_close(p).is_none();
        assert_eq!(by_floor, by_search, "{p:?}");
        refused += usize::from(!by_floor);
    }
    assert!(
        refused > 2_000,
        "the sample reaches the refused space: {refused}"
    );
}
