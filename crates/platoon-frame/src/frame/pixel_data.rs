//! What a method's passes leave per pixel of a band for its work after assembly (IGI's
//! filters, vertex links' solve, the path tracer's world cache and light reuse): records of the
//! method's own types, one stream a kind. The bands' streams join in pixel order kind by kind
//! (`append`) and travel between ranks as each stream's kind, record size and words
//! (`streams`, `push_words`), so the tracer, the renderer, the wire and the method share no
//! convention of strides or offsets: a method reads back the type it wrote, or an error.

use crate::balance::Span;

/// A record a method leaves per pixel: plain data of 4-byte words (f32, u32), named by a kind
/// unique among every method's records (`"method.record"`).
pub trait PixelRecord: bytemuck::Pod {
    const KIND: &'static str;
}

/// One kind's records, in pixel order, as words.
#[derive(Clone, Debug, PartialEq)]
struct Stream {
    kind: String,
    /// Words a record.
    record_words: u32,
    words: Vec<u32>,
    /// Records of another size joined to these (bands of different builds): what reading
    /// them says.
    conflict: Option<String>,
}

/// A band's (or a whole frame's) per-pixel records, by kind.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PixelData {
    streams: Vec<Stream>,
}

/// Words a record of `T`; a record not made of 4-byte words is refused when it is compiled.
const fn record_words<T: PixelRecord>() -> u32 {
    const {
        assert!(std::mem::size_of::<T>().is_multiple_of(4) && std::mem::size_of::<T>() > 0);
        assert!(std::mem::align_of::<T>() <= 4);
    }
    (std::mem::size_of::<T>() / 4) as u32
}

impl PixelData {
    /// Data of one kind, `records`.
    pub fn of<T: PixelRecord>(records: &[T]) -> PixelData {
        let mut d = PixelData::default();
        d.push(records);
        d
    }

    /// Data of one kind, the records of the pixels `span` in `buffer`, which holds one `T` a
    /// pixel (a device buffer, in whatever alignment it is mapped): one copy.
    pub fn of_span<T: PixelRecord>(buffer: &[u8], span: Span) -> PixelData {
        let size = std::mem::size_of::<T>();
        let bytes = &buffer[span.begin as usize * size..span.end as usize * size];
        let words: Vec<u32> = bytemuck::pod_collect_to_vec(bytes);
        let mut d = PixelData::default();
        d.push_words(T::KIND, record_words::<T>(), &words)
            .expect("whole records");
        d
    }

    /// `self` with `records` after its records of their kind.
    pub fn with<T: PixelRecord>(mut self, records: &[T]) -> PixelData {
        self.push(records);
        self
    }

    /// Appends `records` to the stream of their kind (none is made for no records).
    pub fn push<T: PixelRecord>(&mut self, records: &[T]) {
        let words: &[u32] = bytemuck::cast_slice(records);
        self.push_words(T::KIND, record_words::<T>(), words)
            .expect("a kind has one record type");
    }

    /// Appends `words`, records of `record_words` words each, to the stream of `kind`: what
    /// the wire decodes. Refused when they are not whole records or the kind's records have
    /// another size.
    pub fn push_words(
        &mut self,
        kind: &str,
        record_words: u32,
        words: &[u32],
    ) -> Result<(), String> {
        if record_words == 0 || !words.len().is_multiple_of(record_words as usize) {
            return Err(format!(
                "{} words are not whole records of {kind} ({record_words} words each)",
                words.len()
            ));
        }
        if words.is_empty() {
            return Ok(());
        }
        match self.streams.iter_mut().find(|s| s.kind == kind) {
            Some(s) if s.record_words != record_words => Err(format!(
                "records of {kind} of {record_words} words after ones of {}",
                s.record_words
            )),
            Some(s) => {
                s.words.extend_from_slice(words);
                Ok(())
            }
            None => {
                self.streams.push(Stream {
                    kind: kind.to_string(),
                    record_words,
                    words: words.to_vec(),
                    conflict: None,
                });
                Ok(())
            }
        }
    }

    /// `other`'s records after these, kind by kind: the bands' data joined in pixel order when
    /// appended in the order of their spans. Records of a kind whose size differs leave the
    /// kind unreadable (`records` says why).
    pub fn append(&mut self, other: PixelData) {
        for s in other.streams {
            let pushed = self.push_words(&s.kind, s.record_words, &s.words);
            let Some(mine) = self.streams.iter_mut().find(|m| m.kind == s.kind) else {
                continue;
            };
            match (pushed, s.conflict) {
                (Err(e), _) => mine.conflict = Some(e),
                (Ok(()), Some(c)) => {
                    mine.conflict.get_or_insert(c);
                }
                (Ok(()), None) => {}
            }
        }
    }

    /// The records of `T`'s kind, in pixel order (none when there are none); an error when
    /// the stream of its kind holds records of another size.
    pub fn records<T: PixelRecord>(&self) -> Result<&[T], String> {
        let Some(s) = self.streams.iter().find(|s| s.kind == T::KIND) else {
            return Ok(&[]);
        };
        if let Some(c) = &s.conflict {
            return Err(c.clone());
        }
        if s.record_words != record_words::<T>() {
            return Err(format!(
                "the records of {} hold {} words, not the {} of its type",
                T::KIND,
                s.record_words,
                record_words::<T>()
            ));
        }
        Ok(bytemuck::cast_slice(&s.words))
    }

    pub fn is_empty(&self) -> bool {
        self.streams.is_empty()
    }

    /// Each stream's kind, words a record and words (for the wire).
    pub fn streams(&self) -> impl Iterator<Item = (&str, u32, &[u32])> {
        self.streams
            .iter()
            .map(|s| (s.kind.as_str(), s.record_words, s.words.as_slice()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[repr(C)]
    #[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
    struct Two([f32; 2]);
    impl PixelRecord for Two {
        const KIND: &'static str = "test.two";
    }

    #[repr(C)]
    #[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
    struct One(u32);
    impl PixelRecord for One {
        const KIND: &'static str = "test.one";
    }

    /// A second type of the first's kind and another size: a mistake the reader catches.
    #[repr(C)]
    #[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
    struct Three([f32; 3]);
    impl PixelRecord for Three {
        const KIND: &'static str = "test.two";
    }

    #[test]
    fn bands_join_kind_by_kind_in_the_order_appended() {
        let mut first = PixelData::of(&[Two([1.0, 2.0])]).with(&[One(7)]);
        let second = PixelData::of(&[One(8), One(9)]).with(&[Two([3.0, 4.0])]);
        first.append(second);
        assert_eq!(
            first.records::<Two>().unwrap(),
            &[Two([1.0, 2.0]), Two([3.0, 4.0])]
        );
        assert_eq!(first.records::<One>().unwrap(), &[One(7), One(8), One(9)]);
    }

    #[test]
    fn a_kind_read_as_another_size_or_cut_words_are_refused() {
        let d = PixelData::of(&[Two([1.0, 2.0])]);
        assert!(d.records::<Three>().is_err());
        assert_eq!(d.records::<One>().unwrap(), &[]);
        let mut e = PixelData::default();
        assert!(e.push_words("test.two", 2, &[1, 2, 3]).is_err());
        assert!(e.push_words("test.two", 0, &[]).is_err());
        e.push_words("test.two", 2, &[1, 2]).unwrap();
        assert!(e.push_words("test.two", 3, &[1, 2, 3]).is_err());
        let mut joined = PixelData::of(&[Two([1.0, 2.0])]);
        joined.append(PixelData::of(&[Three([1.0, 2.0, 3.0])]));
        assert!(joined.records::<Two>().is_err());
    }

    #[test]
    fn a_device_buffers_span_reads_as_its_records_at_any_alignment() {
        let records = [Two([1.0, 2.0]), Two([3.0, -4.0]), Two([5.0, 6.0])];
        let mut bytes = vec![0u8];
        bytes.extend_from_slice(bytemuck::cast_slice(&records));
        bytes.push(7); // past the buffer's records: not read
        let d = PixelData::of_span::<Two>(&bytes[1..], Span::new(1, 3));
        assert_eq!(d.records::<Two>().unwrap(), &records[1..]);
    }

    #[test]
    fn streams_rebuild_the_same_data() {
        let d = PixelData::of(&[Two([1.0, 2.0])]).with(&[One(7), One(8)]);
        let mut again = PixelData::default();
        for (kind, record_words, words) in d.streams() {
            again.push_words(kind, record_words, words).unwrap();
        }
        assert_eq!(again, d);
        assert!(PixelData::of::<One>(&[]).is_empty());
    }
}
