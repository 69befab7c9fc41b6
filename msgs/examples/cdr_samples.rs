//! Prints one JSON line per message sample: `{"type", "fields", "cdr_hex"}`.
//!
//! Read by `tests/python/test_cdr_equality.py`, which checks every line against rclpy.

fn main() {
    for sample in skyground_msgs::samples::all() {
        println!("{}", sample.to_json_line());
    }
}
