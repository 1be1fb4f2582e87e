//! Writes crates/platoon-accel/src/sheen_albedo_table.rs, the KHR_materials_sheen albedo
//! table the kernel reads (platoon_accel::sheen_albedo):
//! `cargo run -p platoon-accel --example sheen_albedo_table`.

use platoon_accel::sheen_albedo;

fn main() -> std::io::Result<()> {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/src/sheen_albedo_table.rs");
    let text = sheen_albedo::rust_source(&sheen_albedo::table());
    let tmp = format!("{path}.tmp");
    std::fs::write(&tmp, text)?;
    std::fs::rename(&tmp, path)?;
    println!("wrote {path}");
    Ok(())
}
