//! Variance of the unshadowed-irradiance estimator, area sampling vs the better techniques, for
//! the configurations of issue 5 (receiver at the origin facing +Z, light above it).
//!
//! Run: `cargo run -p lux-sample --release --example variance`

#[path = "../tests/common/mod.rs"]
mod common;

fn main() {
    let n = 1_000_000;
    let r = common::ratio_receiver();
    println!(
        "{:<26} {:<36} {:>12} {:>14} {:>10}",
        "configuration", "technique", "E", "var/sample", "ratio"
    );
    for case in common::ratio_cases() {
        let (e_area, v_area) = common::estimator_variance(&case.area, &r, n, 1);
        println!(
            "{:<26} {:<36} {:>12.6} {:>14.6e} {:>10}",
            case.name, "area (hdEmbree)", e_area, v_area, "1"
        );
        for (name, light) in &case.better {
            let (e, v) = common::estimator_variance(light, &r, n, 2);
            println!(
                "{:<26} {:<36} {:>12.6} {:>14.6e} {:>10.2}",
                "",
                name,
                e,
                v,
                v_area / v
            );
        }
    }
}
