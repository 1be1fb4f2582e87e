//! A flag of a described value (a method's setting, a request's option): its kind decides
//! whether it takes a value and how the value is read (`Value::parse`), so `method_args` and
//! `request_args` make their flags and read them back the same way.

use clap::{Arg, ArgAction, ArgMatches};
use platoon::core::method::settings::{Value, ValueKind};

/// `arg` taking a value of `kind` (a switch takes none).
pub fn of_kind(arg: Arg, kind: ValueKind) -> Arg {
    match kind {
        ValueKind::Switch => arg.action(ArgAction::SetTrue),
        // The flag alone is its first choice.
        ValueKind::Mode(choices) => arg
            .num_args(0..=1)
            .default_missing_value(choices[0])
            .value_parser(move |text: &str| Value::parse(kind, text)),
        kind => arg.value_parser(move |text: &str| Value::parse(kind, text)),
    }
}

/// The value given to the flag `id` of `kind`, if any.
pub fn given(m: &ArgMatches, id: &str, kind: ValueKind) -> Option<Value> {
    match kind {
        ValueKind::Switch => m.get_flag(id).then_some(Value::Switch(true)),
        _ => m.get_one::<Value>(id).cloned(),
    }
}
