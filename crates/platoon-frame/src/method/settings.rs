//! A method's options described once (`Setting`), and values of them (`Settings`). The command
//! line's flags, the lab's technique strings (`technique`) and the wire of MPI are all made from
//! the description, so no layer above a method names its options.

use std::fmt;

/// What a setting holds, and so how it is written.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ValueKind {
    /// A whole number.
    Count,
    /// A real number.
    Number,
    /// On or off: a flag without a value.
    Switch,
    /// Two whole numbers written MxN.
    Tile,
    /// One word: of `choices`, or any the method parses when `choices` is empty (layered hit
    /// buffers' direction sets: ico320, oct32, halton144...).
    Word(&'static [&'static str]),
    /// One word of `choices`, the first when the flag is given alone (`--light-reuse` is
    /// `--light-reuse unbiased`).
    Mode(&'static [&'static str]),
}

/// A value of a setting.
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    Count(u32),
    Number(f32),
    Switch(bool),
    Tile([u32; 2]),
    Word(String),
}

/// One option of a method.
#[derive(Debug)]
pub struct Setting {
    /// Its name among the method's settings (and on the wire).
    pub key: &'static str,
    /// Its command-line flag, without the dashes (unique among every method's).
    pub flag: &'static str,
    /// Its word in technique strings: the prefix written before the value (`b` in `+b2`), or
    /// the switch itself (`+boxes`); None where techniques do not set it. A `Word` with
    /// choices is set by the choice alone (`+exact`).
    pub token: Option<&'static str>,
    pub kind: ValueKind,
    pub help: &'static str,
}

impl Value {
    /// `text` read as a value of `kind`.
    pub fn parse(kind: ValueKind, text: &str) -> Result<Value, String> {
        let text = text.trim();
        match kind {
            ValueKind::Count => text
                .parse()
                .map(Value::Count)
                .map_err(|_| format!("{text:?} is not a whole number")),
            ValueKind::Number => match text.parse::<f32>() {
                Ok(v) if v.is_finite() => Ok(Value::Number(v)),
                _ => Err(format!("{text:?} is not a finite number")),
            },
            ValueKind::Switch => match text {
                "" | "on" | "true" => Ok(Value::Switch(true)),
                "off" | "false" => Ok(Value::Switch(false)),
                _ => Err(format!("{text:?} is not on or off")),
            },
            ValueKind::Tile => {
                let bad = || format!("{text:?}: a tile is MxN, e.g. 3x3");
                let (m, n) = text.split_once(['x', 'X']).ok_or_else(bad)?;
                Ok(Value::Tile([
                    m.trim().parse().map_err(|_| bad())?,
                    n.trim().parse().map_err(|_| bad())?,
                ]))
            }
            ValueKind::Word(choices) | ValueKind::Mode(choices)
                if !choices.is_empty() && !choices.contains(&text) =>
            {
                Err(format!("{text:?} is not one of {}", choices.join(", ")))
            }
            ValueKind::Word(_) if text.is_empty() => Err("an empty word".into()),
            ValueKind::Word(_) | ValueKind::Mode(_) => Ok(Value::Word(text.to_string())),
        }
    }
}

impl fmt::Display for Value {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Value::Count(n) => write!(f, "{n}"),
            Value::Number(v) => write!(f, "{v}"),
            Value::Switch(on) => write!(f, "{}", if *on { "on" } else { "off" }),
            Value::Tile([m, n]) => write!(f, "{m}x{n}"),
            Value::Word(w) => write!(f, "{w}"),
        }
    }
}

/// Values of some of a method's settings, by key, in the order they were given.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Settings(pub Vec<(&'static str, Value)>);

impl Eq for Settings {}

impl std::hash::Hash for Settings {
    fn hash<H: std::hash::Hasher>(&self, h: &mut H) {
        for (key, value) in &self.0 {
            key.hash(h);
            value.to_string().hash(h);
        }
    }
}

impl Settings {
    /// Sets `key` to `value`, replacing what it had.
    pub fn set(&mut self, key: &'static str, value: Value) {
        match self.0.iter_mut().find(|(k, _)| *k == key) {
            Some(entry) => entry.1 = value,
            None => self.0.push((key, value)),
        }
    }

    pub fn get(&self, key: &str) -> Option<&Value> {
        self.0.iter().find(|(k, _)| *k == key).map(|(_, v)| v)
    }

    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    /// `key`'s whole number, if given (a value of another kind is a method's mistake).
    pub fn count(&self, key: &str) -> Option<u32> {
        self.get(key)
            .map(|v| v.count().unwrap_or_else(|e| panic!("setting {key}: {e}")))
    }

    pub fn number(&self, key: &str) -> Option<f32> {
        self.get(key)
            .map(|v| v.number().unwrap_or_else(|e| panic!("setting {key}: {e}")))
    }

    pub fn switch(&self, key: &str) -> Option<bool> {
        self.get(key)
            .map(|v| v.switch().unwrap_or_else(|e| panic!("setting {key}: {e}")))
    }

    pub fn tile(&self, key: &str) -> Option<[u32; 2]> {
        self.get(key)
            .map(|v| v.tile().unwrap_or_else(|e| panic!("setting {key}: {e}")))
    }

    pub fn word(&self, key: &str) -> Option<&str> {
        self.get(key)
            .map(|v| v.word().unwrap_or_else(|e| panic!("setting {key}: {e}")))
    }
}

impl Value {
    /// The whole number it holds; another kind is an error saying so.
    pub fn count(&self) -> Result<u32, String> {
        match self {
            Value::Count(n) => Ok(*n),
            other => Err(format!("a count, not {other:?}")),
        }
    }

    /// The number it holds (a whole number too).
    pub fn number(&self) -> Result<f32, String> {
        match self {
            Value::Number(v) => Ok(*v),
            Value::Count(n) => Ok(*n as f32),
            other => Err(format!("a number, not {other:?}")),
        }
    }

    pub fn switch(&self) -> Result<bool, String> {
        match self {
            Value::Switch(on) => Ok(*on),
            other => Err(format!("a switch, not {other:?}")),
        }
    }

    pub fn tile(&self) -> Result<[u32; 2], String> {
        match self {
            Value::Tile(t) => Ok(*t),
            other => Err(format!("a tile, not {other:?}")),
        }
    }

    pub fn word(&self) -> Result<&str, String> {
        match self {
            Value::Word(w) => Ok(w),
            other => Err(format!("a word, not {other:?}")),
        }
    }
}

/// How a setting is written in the list of a technique's options: `boxes`, `downK`,
/// `interMxN`, `minX`, `capacity|exact`.
pub fn token_form(s: &Setting) -> Option<String> {
    let token = s.token;
    match s.kind {
        ValueKind::Word(choices) | ValueKind::Mode(choices) if !choices.is_empty() => {
            Some(choices.join("|"))
        }
        ValueKind::Switch => token.map(str::to_string),
        ValueKind::Count => token.map(|t| format!("{t}N")),
        ValueKind::Number => token.map(|t| format!("{t}X")),
        ValueKind::Tile => token.map(|t| format!("{t}MxN")),
        ValueKind::Word(_) | ValueKind::Mode(_) => token.map(|t| format!("{t}WORD")),
    }
}
