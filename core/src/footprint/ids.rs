//! A footprint's own id, as the survey that made it numbers its buildings:
//! BAG `identificatie`, an OSM id, a CityObject id, or a field the user names.

use serde_json::{Map, Value};

use super::error::{ParseError, shape};

/// Properties (GeoJSON, FlatGeobuf) and attributes (CityJSON) that hold a
/// building's own id, tried in this order: BAG (`identificatie`, PDOK and
/// 3DBAG), BAG through BGT (`identificatiebagpnd`, 3dfier), skyground's own
/// outputs (`footprint_id`), then the ids OSM exports carry (`id`,
/// overpass-turbo's `@id`, ogr2ogr's `osm_id`).
pub const ID_FIELDS: [&str; 6] = [
    "identificatie",
    "identificatiebagpnd",
    "footprint_id",
    "id",
    "@id",
    "osm_id",
];

/// How a reader picks each footprint's own id.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct ReadOptions {
    /// The property or attribute that holds it (`--footprint-id FIELD`);
    /// `None`: the first of [`ID_FIELDS`] present, else the feature's or
    /// CityObject's own id.
    pub id_field: Option<String>,
    /// CityJSON: a footprint per BuildingPart (its Building's own id in
    /// [`Loaded::part_of`](super::Loaded)) instead of one per Building.
    pub parts: bool,
}

/// A property value as id text: a non-empty string or a number.
pub(crate) fn id_text(v: &Value) -> Option<String> {
    match v {
        Value::String(s) => Some(s.trim().to_string()).filter(|s| !s.is_empty()),
        Value::Number(n) => Some(n.to_string()),
        _ => None,
    }
}

/// The own id in `props`: the named field when one is named, else the first
/// of [`ID_FIELDS`] present.
pub(crate) fn own_id(props: Option<&Map<String, Value>>, options: &ReadOptions) -> Option<String> {
    let props = props?;
    match &options.id_field {
        Some(field) => props.get(field).and_then(id_text),
        None => ID_FIELDS
            .iter()
            .find_map(|k| props.get(*k).and_then(id_text)),
    }
}

/// A named id field that no feature carries is the user's mistake, said
/// with the fields the first one does carry.
pub(crate) fn check_named_field(
    options: &ReadOptions,
    found: usize,
    first_props: Option<&Map<String, Value>>,
) -> Result<(), ParseError> {
    let Some(field) = &options.id_field else {
        return Ok(());
    };
    if found > 0 {
        return Ok(());
    }
    let seen: Vec<&str> = first_props
        .map(|p| p.keys().map(String::as_str).collect())
        .unwrap_or_default();
    Err(shape(&format!(
        "no footprint has the id field `{field}` (--footprint-id); the first one has: {}",
        if seen.is_empty() {
            "no properties".to_string()
        } else {
            seen.join(", ")
        }
    )))
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn the_first_known_id_field_or_the_named_one() {
        let p = json!({"name": "Oude Kerk", "osm_id": 1234, "@id": "way/99"});
        let p = p.as_object();
        assert_eq!(
            own_id(p, &ReadOptions::default()).as_deref(),
            Some("way/99")
        );
        let named = ReadOptions {
            id_field: Some("name".into()),
            ..ReadOptions::default()
        };
        assert_eq!(own_id(p, &named).as_deref(), Some("Oude Kerk"));
        let bag = json!({"identificatie": "0503100000028341", "id": 3});
        assert_eq!(
            own_id(bag.as_object(), &ReadOptions::default()).as_deref(),
            Some("0503100000028341")
        );
        let absent = ReadOptions {
            id_field: Some("fid".into()),
            ..ReadOptions::default()
        };
        assert_eq!(own_id(p, &absent), None);
        let e = check_named_field(&absent, 0, p).expect_err("no feature has it");
        assert!(
            e.to_string().contains("`fid`") && e.to_string().contains("osm_id"),
            "{e}"
        );
        assert!(check_named_field(&absent, 1, p).is_ok());
    }
}
