//! A plain-data array in serde as one byte string (`#[serde(with = "pod_bytes")]`): a frame's
//! large tables (the world cache's, the reservoirs) travel bit for bit and at the speed of a
//! copy, where serde's default would write every float as an item of its own.

use serde::de::{Error as _, Visitor};
use serde::{Deserializer, Serializer};

pub fn serialize<T: bytemuck::Pod, S: Serializer>(v: &[T], s: S) -> Result<S::Ok, S::Error> {
    s.serialize_bytes(bytemuck::cast_slice(v))
}

pub fn deserialize<'de, T: bytemuck::Pod, D: Deserializer<'de>>(d: D) -> Result<Vec<T>, D::Error> {
    struct Bytes;
    impl<'de> Visitor<'de> for Bytes {
        type Value = Vec<u8>;
        fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
            f.write_str("a byte string")
        }
        fn visit_bytes<E: serde::de::Error>(self, v: &[u8]) -> Result<Vec<u8>, E> {
            Ok(v.to_vec())
        }
        fn visit_byte_buf<E: serde::de::Error>(self, v: Vec<u8>) -> Result<Vec<u8>, E> {
            Ok(v)
        }
    }
    let bytes = d.deserialize_byte_buf(Bytes)?;
    let size = std::mem::size_of::<T>();
    if !bytes.len().is_multiple_of(size) {
        return Err(D::Error::custom(format!(
            "{} bytes are not whole values of {size} bytes",
            bytes.len()
        )));
    }
    // Copied: the bytes need not be aligned for T.
    Ok(bytemuck::pod_collect_to_vec(&bytes))
}
