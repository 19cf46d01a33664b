//! Prints a MaterialX document as the `.usda` layer lux composes it as (usdMtlx's prim
//! layout; `usdcat doc.mtlx` with usd-core's usdMtlx plugin prints the same structure):
//!
//! ```text
//! cargo run -p lux-usd --example mtlx_to_usda -- path/to/doc.mtlx > doc.mtlx.usda
//! ```

use std::process::ExitCode;

fn main() -> ExitCode {
    let Some(path) = std::env::args().nth(1) else {
        eprintln!("usage: mtlx_to_usda DOC.mtlx");
        return ExitCode::from(2);
    };
    match lux_usd::mtlx::read_document(std::path::Path::new(&path)) {
        Ok(doc) => {
            print!("{}", lux_usd::mtlx::usdmtlx::to_usda(&doc));
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("{e}");
            ExitCode::FAILURE
        }
    }
}
