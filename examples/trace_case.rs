// Temporary: trace one reference case. Usage: trace_case FILE INDEX
use serde_json::Value;
#[path = "../tests/common/mod.rs"]
mod common;
fn main() {
    let a: Vec<String> = std::env::args().collect();
    let cases = common::load(std::path::Path::new(&a[1]));
    let c: &Value = &cases[a[2].parse::<usize>().unwrap()];
    let p = dcol::proximity(
        &common::shape(&c["shape1"]),
        &common::pose(&c["pose1"]),
        &common::shape(&c["shape2"]),
        &common::pose(&c["pose2"]),
        &Default::default(),
    )
    .unwrap();
    println!("{:?}\nref alpha {}", p, c["alpha"]);
}
