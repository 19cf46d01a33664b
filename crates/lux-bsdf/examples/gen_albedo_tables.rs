//! Writes `src/albedo_tables.bin`, the directional-albedo tables lux-bsdf reads (computed by
//! quadrature in `albedo::generate`; a unit test checks the committed file against it):
//! `cargo run --release -p lux-bsdf --example gen_albedo_tables`.

fn main() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/src/albedo_tables.bin");
    let bytes = lux_bsdf::albedo::generate();
    std::fs::write(path, &bytes).expect("write albedo_tables.bin");
    println!("wrote {} bytes to {path}", bytes.len());
}
