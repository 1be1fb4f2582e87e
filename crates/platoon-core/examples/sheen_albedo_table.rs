//! Writes crates/platoon-core/src/flatten/sheen_albedo_table.rs, the KHR_materials_sheen albedo
//! table the kernel reads (platoon_core::flatten::sheen_albedo):
//! `cargo run -p platoon-core --example sheen_albedo_table`.

use platoon_core::flatten::sheen_albedo;

fn main() -> std::io::Result<()> {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/src/flatten/sheen_albedo_table.rs"
    );
    let text = sheen_albedo::rust_source(&sheen_albedo::table());
    let tmp = format!("{path}.tmp");
    std::fs::write(&tmp, text)?;
    std::fs::rename(&tmp, path)?;
    println!("wrote {path}");
    Ok(())
}
