//! The rendering method's flags, made from the methods' own descriptions (the core's
//! `method::registry::all`): `--method NAME` and one flag per setting of every method
//! (`--kernel`, `--resampled-light`, `--vpls`, `--links-directions`...), so this file names
//! no method.

use anyhow::{bail, Result};
use clap::builder::{PossibleValue, PossibleValuesParser};
use clap::{Arg, ArgMatches, Command};
use platoon::core::method::kind::MethodKind;
use platoon::core::method::registry;
use platoon::core::method::settings::{Setting, Settings};
use platoon::core::Method;

use crate::value_arg::{given, of_kind};

/// The method chosen and every setting given on the command line, of any method.
#[derive(Debug)]
pub struct MethodArgs {
    pub method: &'static dyn MethodKind,
    given: Given,
}

/// Each method's settings given, with the flags that gave them.
pub type Given = Vec<(&'static dyn MethodKind, Settings, Vec<&'static str>)>;

/// Which of a kind's described settings: its options (`settings`) or what it learns over
/// frames (`learning_settings`).
pub type SettingsOf = fn(&dyn MethodKind) -> &'static [Setting];

/// `cmd` with a flag for each setting of every method that `of` picks.
pub fn with_flags(cmd: Command, of: SettingsOf) -> Command {
    registry::all().into_iter().fold(cmd, |cmd, kind| {
        of(kind).iter().fold(cmd, |cmd, s| {
            let help = format!("{}: {}", kind.title(), s.help);
            cmd.arg(of_kind(Arg::new(s.flag).long(s.flag).help(help), s.kind))
        })
    })
}

/// The settings of every method that `of` picks given in `m`.
pub fn given_in(m: &ArgMatches, of: SettingsOf) -> Given {
    registry::all()
        .into_iter()
        .map(|kind| {
            let mut settings = Settings::default();
            let mut flags = Vec::new();
            for s in of(kind) {
                if let Some(v) = given(m, s.flag, s.kind) {
                    settings.set(s.key, v);
                    flags.push(s.flag);
                }
            }
            (kind, settings, flags)
        })
        .collect()
}

/// What of `given` is `kind`'s; an error where flags of another method were given.
pub fn given_to(given: &Given, kind: &dyn MethodKind) -> Result<Settings> {
    for (k, _, flags) in given {
        if k.name() != kind.name() && !flags.is_empty() {
            bail!(
                "--{} sets {}: add --method {}",
                flags.join(", --"),
                k.title(),
                k.name()
            );
        }
    }
    Ok(given
        .iter()
        .find(|(k, _, _)| k.name() == kind.name())
        .map(|(_, s, _)| s.clone())
        .unwrap_or_default())
}

/// `error` of a kind's `build` or `with_learning`, the setting it is about written as its flag.
pub fn as_flag(kind: &dyn MethodKind, error: String) -> anyhow::Error {
    match kind.split_setting(&error) {
        Some((setting, problem)) => anyhow::anyhow!("--{}: {problem}", setting.flag),
        None => anyhow::Error::msg(error),
    }
}

impl MethodArgs {
    /// The method with its options; refuses one method's flags given to another.
    pub fn method(&self) -> Result<Method> {
        let given = given_to(&self.given, self.method)?;
        (self.method.build(&given)).map_err(|e| as_flag(self.method, e))
    }
}

/// `--method`'s values, each with its summary.
fn method_values() -> PossibleValuesParser {
    PossibleValuesParser::new(
        registry::all()
            .into_iter()
            .map(|k| PossibleValue::new(k.name()).help(k.summary())),
    )
}

impl clap::Args for MethodArgs {
    fn augment_args(cmd: Command) -> Command {
        let cmd = cmd.arg(
            Arg::new("method")
                .long("method")
                .help("Rendering method.")
                .value_parser(method_values())
                .default_value(registry::KINDS[0].name()),
        );
        with_flags(cmd, |k| k.settings())
    }

    fn augment_args_for_update(cmd: Command) -> Command {
        Self::augment_args(cmd)
    }
}

impl clap::FromArgMatches for MethodArgs {
    fn from_arg_matches(m: &ArgMatches) -> Result<Self, clap::Error> {
        let name = m
            .get_one::<String>("method")
            .map(String::as_str)
            .unwrap_or(registry::KINDS[0].name());
        let method = registry::kind(name).ok_or_else(|| {
            clap::Error::raw(
                clap::error::ErrorKind::InvalidValue,
                format!("unknown method {name}: one of {}", registry::names()),
            )
        })?;
        let given = given_in(m, |k| k.settings());
        Ok(MethodArgs { method, given })
    }

    fn update_from_arg_matches(&mut self, m: &ArgMatches) -> Result<(), clap::Error> {
        *self = Self::from_arg_matches(m)?;
        Ok(())
    }
}
