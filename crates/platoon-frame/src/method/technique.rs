//! A method in the lab's technique strings, read and written from its description alone:
//! `NAME=PRIMARY+OPTION+...`, an option being a switch's word (`boxes`), a choice (`exact`),
//! a preset (`all`) or a token followed by its value (`down4`, `inter3x3`, `min0.1`).

use super::kind::MethodKind;
use super::settings::{token_form, Settings, Value, ValueKind};

/// The settings `value` (what follows `NAME=` in the technique `whole`) gives, validated.
pub fn parse(kind: &dyn MethodKind, whole: &str, value: &str) -> Result<Settings, String> {
    let mut parts = value.split('+').map(str::trim);
    let mut given = Settings::default();
    if let Some(key) = kind.primary() {
        let setting = kind.setting(key).expect("the primary is a setting");
        match parts.next().map(|p| Value::parse(setting.kind, p)) {
            Some(Ok(v)) => given.set(key, v),
            _ => {
                let example = kind
                    .sweep()
                    .iter()
                    .find(|t| t.starts_with(&format!("{}=", kind.name())))
                    .unwrap_or(&"");
                return Err(format!(
                    "technique {whole:?}: {} needs its {} first, e.g. {example}",
                    kind.name(),
                    setting.key.replace('_', " ")
                ));
            }
        }
    }
    for part in parts {
        set_option(kind, &mut given, part).map_err(|e| format!("technique {whole:?}: {e}"))?;
    }
    kind.build(&given)
        .map_err(|e| format!("technique {whole:?}: {e}"))?;
    Ok(given)
}

/// Sets what the option `part` names.
fn set_option(kind: &dyn MethodKind, given: &mut Settings, part: &str) -> Result<(), String> {
    if let Some((_, values)) = kind.presets().iter().find(|(name, _)| *name == part) {
        for (key, text) in values.iter() {
            let setting = kind.setting(key).expect("a preset names settings");
            let value = Value::parse(setting.kind, text).expect("a preset's values parse");
            given.set(setting.key, value);
        }
        return Ok(());
    }
    for s in kind.settings() {
        match s.kind {
            ValueKind::Switch if s.token == Some(part) => {
                given.set(s.key, Value::Switch(true));
                return Ok(());
            }
            ValueKind::Word(choices) if choices.contains(&part) => {
                given.set(s.key, Value::Word(part.to_string()));
                return Ok(());
            }
            _ => {}
        }
    }
    // The longest token that prefixes `part` with a value of its kind after it.
    let valued = kind.settings().iter().filter_map(|s| {
        let token = s.token?;
        let rest = part.strip_prefix(token).filter(|r| !r.is_empty())?;
        let by_value = !matches!(s.kind, ValueKind::Switch);
        let value = Value::parse(s.kind, rest).ok().filter(|_| by_value)?;
        Some((token.len(), s.key, value))
    });
    match valued.max_by_key(|(len, _, _)| *len) {
        Some((_, key, value)) => {
            given.set(key, value);
            Ok(())
        }
        None => {
            let forms: Vec<String> = kind
                .settings()
                .iter()
                .filter(|s| Some(s.key) != kind.primary())
                .filter_map(token_form)
                .chain(kind.presets().iter().map(|(name, _)| name.to_string()))
                .collect();
            Err(format!(
                "unknown {} option {part:?} ({})",
                kind.title(),
                forms.join(", ")
            ))
        }
    }
}

/// The technique string of `given`: its primary, then each option that differs from the
/// default in the settings' order, a preset's name where all of its values hold.
pub fn format(kind: &dyn MethodKind, given: &Settings) -> String {
    let defaults = kind.defaults();
    let value = |key: &str| given.get(key).or_else(|| defaults.get(key));
    let mut out = kind.name().to_string();
    if let Some(v) = kind.primary().and_then(value) {
        out += &format!("={v}");
    }
    let mut covered: Vec<&str> = Vec::new();
    for (name, values) in kind.presets() {
        let holds = values.iter().all(|(key, text)| {
            let setting = kind.setting(key).expect("a preset names settings");
            Value::parse(setting.kind, text).ok().as_ref() == value(key)
        });
        if holds {
            out += &format!("+{name}");
            covered.extend(values.iter().map(|(key, _)| *key));
        }
    }
    for s in kind.settings() {
        if Some(s.key) == kind.primary() || covered.contains(&s.key) {
            continue;
        }
        let (Some(v), Some(d)) = (value(s.key), defaults.get(s.key)) else {
            continue;
        };
        if v == d {
            continue;
        }
        match (s.kind, v, s.token) {
            (ValueKind::Word(choices), Value::Word(w), _) if !choices.is_empty() => {
                out += &format!("+{w}")
            }
            (ValueKind::Switch, Value::Switch(true), Some(token)) => out += &format!("+{token}"),
            (ValueKind::Switch, _, _) => {}
            (_, v, Some(token)) => out += &format!("+{token}{v}"),
            _ => {}
        }
    }
    out
}
