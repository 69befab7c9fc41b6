//! The merged parameters as ROS 2 parameters (what `ros2 param list/get/set`
//! and rclpy's parameter client call): every value is declared through
//! ros2-client's parameter services; a set is refused for a name the node
//! does not know (ros2-client), with another type (ros2-client), and for a
//! parameter the node reads once at start-up (here, with the way to change
//! it). Parameters a node reads again as it works ([`NodeSpec::live`]) are
//! written back to the node's live set.

use std::sync::{Arc, Mutex};

use ros2_client::NodeOptions;
use ros2_client::parameters::ParameterValue;
use serde_json::Value;

use super::params::ParamSet;
use super::specs::NodeSpec;

/// A JSON parameter value as a ROS 2 parameter value. Arrays take the type
/// of their elements (an empty one is a double array: ours hold
/// coordinates); anything else ROS 2 cannot type (mixed or nested arrays,
/// mappings) is its JSON text.
pub fn to_ros(v: &Value) -> ParameterValue {
    match v {
        Value::Null => ParameterValue::NotSet,
        Value::Bool(b) => ParameterValue::Boolean(*b),
        Value::Number(n) => match n.as_i64() {
            Some(i) => ParameterValue::Integer(i),
            None => ParameterValue::Double(n.as_f64().unwrap_or(f64::NAN)),
        },
        Value::String(s) => ParameterValue::String(s.clone()),
        Value::Array(a) => {
            if a.is_empty() || a.iter().all(|x| x.is_number()) {
                match a.iter().map(Value::as_i64).collect::<Option<Vec<_>>>() {
                    Some(ints) if !a.is_empty() => ParameterValue::IntegerArray(ints),
                    _ => ParameterValue::DoubleArray(a.iter().filter_map(Value::as_f64).collect()),
                }
            } else if let Some(b) = a.iter().map(Value::as_bool).collect::<Option<Vec<_>>>() {
                ParameterValue::BooleanArray(b)
            } else if let Some(s) = a
                .iter()
                .map(|x| x.as_str().map(str::to_string))
                .collect::<Option<Vec<_>>>()
            {
                ParameterValue::StringArray(s)
            } else {
                ParameterValue::String(v.to_string())
            }
        }
        Value::Object(_) => ParameterValue::String(v.to_string()),
    }
}

/// A ROS 2 parameter value as the JSON the node's parameter struct reads.
pub fn to_json(v: &ParameterValue) -> Value {
    match v {
        ParameterValue::NotSet => Value::Null,
        ParameterValue::Boolean(b) => Value::Bool(*b),
        ParameterValue::Integer(i) => Value::from(*i),
        ParameterValue::Double(d) => Value::from(*d),
        ParameterValue::String(s) => Value::String(s.clone()),
        ParameterValue::ByteArray(a) => Value::from(a.clone()),
        ParameterValue::BooleanArray(a) => Value::from(a.clone()),
        ParameterValue::IntegerArray(a) => Value::from(a.clone()),
        ParameterValue::DoubleArray(a) => Value::from(a.clone()),
        ParameterValue::StringArray(a) => Value::from(a.clone()),
    }
}

/// Whether `name` is one of the node's live parameters (an entry ending in
/// `.` takes every name under it).
pub fn is_live(live: &[&str], name: &str) -> bool {
    live.iter().any(|l| {
        if l.ends_with('.') {
            name.starts_with(l)
        } else {
            *l == name
        }
    })
}

/// The check of a set: a start-up parameter keeps its value (setting the
/// same value is accepted, as ros2-client checks the declarations too).
pub fn check_set(
    node: &str,
    live: &[&str],
    start: &ParamSet,
    name: &str,
    value: &ParameterValue,
) -> Result<(), String> {
    if name == "use_sim_time" || is_live(live, name) {
        return Ok(());
    }
    match start.get(name) {
        Some(v) if to_ros(v) == *value => Ok(()),
        _ => Err(format!(
            "{node}: `{name}` is read once at start-up; restart the node with `--ros-args -p {name}:=VALUE` (or a --params-file) to change it"
        )),
    }
}

/// `options` with every merged parameter declared, the start-up check and
/// the write-back of live parameters into `current`.
pub fn declare(
    options: NodeOptions,
    spec: &NodeSpec,
    name: &str,
    params: &ParamSet,
    current: Arc<Mutex<ParamSet>>,
) -> NodeOptions {
    let mut options = options
        .start_parameter_services(true)
        .allow_undeclared_parameters(false);
    for (k, v) in params.entries() {
        options = options.declare_parameter(&k, to_ros(&v));
    }
    let (node, live, start) = (name.to_string(), spec.live, params.clone());
    options
        .parameter_validator(Box::new(move |n, v| check_set(&node, live, &start, n, v)))
        .parameter_set_action(Box::new(move |n, v| {
            if let Ok(mut set) = current.lock() {
                set.set(n, to_json(v));
            }
            Ok(())
        }))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn json_values_take_their_ros_types_and_come_back() {
        let cases = [
            (serde_json::json!(true), ParameterValue::Boolean(true)),
            (serde_json::json!(3), ParameterValue::Integer(3)),
            (serde_json::json!(2.5), ParameterValue::Double(2.5)),
            (
                serde_json::json!("map"),
                ParameterValue::String("map".into()),
            ),
            (
                serde_json::json!([1, 2]),
                ParameterValue::IntegerArray(vec![1, 2]),
            ),
            (
                serde_json::json!([1.5, 2]),
                ParameterValue::DoubleArray(vec![1.5, 2.0]),
            ),
            (
                serde_json::json!(["/local_path"]),
                ParameterValue::StringArray(vec!["/local_path".into()]),
            ),
            (
                serde_json::json!([true, false]),
                ParameterValue::BooleanArray(vec![true, false]),
            ),
        ];
        for (json, ros) in cases {
            assert_eq!(to_ros(&json), ros, "{json}");
            assert_eq!(to_json(&ros).as_f64(), json.as_f64());
        }
        assert_eq!(
            to_ros(&serde_json::json!([])),
            ParameterValue::DoubleArray(vec![])
        );
        assert_eq!(
            to_ros(&serde_json::json!([[0, 1], [2, 3]])),
            ParameterValue::String("[[0,1],[2,3]]".into())
        );
    }

    #[test]
    fn start_up_parameters_refuse_a_new_value_with_the_way_to_change_it() {
        let mut start = ParamSet::default();
        start.set("frame_id", serde_json::json!("map"));
        start.set("follow.stall_timeout_s", serde_json::json!(30.0));
        let live = &["follow."];
        // The declared value itself passes (ros2-client checks declarations).
        assert!(
            check_set(
                "n",
                live,
                &start,
                "frame_id",
                &ParameterValue::String("map".into())
            )
            .is_ok()
        );
        let e = check_set(
            "n",
            live,
            &start,
            "frame_id",
            &ParameterValue::String("odom".into()),
        )
        .unwrap_err();
        assert!(
            e.contains("read once at start-up") && e.contains("-p frame_id:="),
            "{e}"
        );
        assert!(
            check_set(
                "n",
                live,
                &start,
                "follow.stall_timeout_s",
                &ParameterValue::Double(5.0)
            )
            .is_ok()
        );
        assert!(is_live(&["max_clouds"], "max_clouds") && !is_live(&["max_clouds"], "max"));
    }
}
