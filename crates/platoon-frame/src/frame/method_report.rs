//! What a method's passes report of a band (layered hit buffers' build: what it made and what
//! it cost on the device): a value of the method's own type, encoded by serde (CBOR) under its
//! kind, so that it travels between ranks as it is and the method reads back the type it wrote.
//! The method's core half turns it into the image's metadata and what a user reads
//! (`RenderMethod::report_metadata`, `RenderMethod::report`); a bench reads its numbers.

use serde::de::DeserializeOwned;
use serde::Serialize;

/// A method's report of a band, named by a kind unique among every method's (`"method.what"`).
pub trait ReportValue: Serialize + DeserializeOwned {
    const KIND: &'static str;
}

/// A band's report, of one method's type; empty for methods that report nothing.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MethodReport {
    kind: String,
    bytes: Vec<u8>,
}

impl MethodReport {
    pub fn of<T: ReportValue>(value: &T) -> MethodReport {
        let mut bytes = Vec::new();
        // Into memory: only a value serde cannot write fails, which a report's type is not.
        ciborium::into_writer(value, &mut bytes).expect("a report encodes");
        MethodReport {
            kind: T::KIND.into(),
            bytes,
        }
    }

    /// The report as `T`; None when it is of another kind (or empty), an error when its
    /// bytes do not read as `T`.
    pub fn read<T: ReportValue>(&self) -> Option<Result<T, String>> {
        (self.kind == T::KIND).then(|| {
            ciborium::from_reader(self.bytes.as_slice())
                .map_err(|e| format!("the {} report: {e}", T::KIND))
        })
    }

    /// The report as `T` where it is one and its bytes read (what a reader that only shows or
    /// measures it wants: anything else is no `T`).
    pub fn value<T: ReportValue>(&self) -> Option<T> {
        self.read::<T>()?.ok()
    }

    pub fn is_empty(&self) -> bool {
        self.kind.is_empty()
    }

    /// Its kind and bytes (for the wire).
    pub fn parts(&self) -> (&str, &[u8]) {
        (&self.kind, &self.bytes)
    }

    /// What `parts` gave.
    pub fn from_parts(kind: String, bytes: Vec<u8>) -> MethodReport {
        MethodReport { kind, bytes }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug, PartialEq, serde::Serialize, serde::Deserialize)]
    struct Built {
        bytes: u64,
        seconds: f64,
        kept: Option<(bool, u32)>,
    }
    impl ReportValue for Built {
        const KIND: &'static str = "test.built";
    }

    #[derive(Debug, PartialEq, serde::Serialize, serde::Deserialize)]
    struct Other(u32);
    impl ReportValue for Other {
        const KIND: &'static str = "test.other";
    }

    #[test]
    fn a_report_reads_back_as_its_own_type_only() {
        let built = Built {
            bytes: 1 << 40,
            seconds: 0.125,
            kept: Some((true, 3)),
        };
        let r = MethodReport::of(&built);
        assert_eq!(r.read::<Built>().unwrap().unwrap(), built);
        assert!(r.read::<Other>().is_none());
        assert!(MethodReport::default().read::<Built>().is_none());
        let (kind, bytes) = r.parts();
        let again = MethodReport::from_parts(kind.into(), bytes.to_vec());
        assert_eq!(again, r);
        let cut = MethodReport::from_parts(kind.into(), bytes[..bytes.len() - 1].to_vec());
        assert!(cut.read::<Built>().unwrap().is_err());
        // A value is the report's where it reads, none where it does not.
        assert_eq!(r.value::<Built>(), Some(built));
        assert!(cut.value::<Built>().is_none() && r.value::<Other>().is_none());
    }
}
