//! The rendering method's flags, made from the methods' own descriptions (the core's
//! `method::registry::all`): `--method NAME` and one flag per setting of every method
//! (`--kernel`, `--resampled-light`, `--vpls`, `--links-directions`...), so this file names
//! no method.

use anyhow::{bail, Result};
use clap::builder::{PossibleValue, PossibleValuesParser};
use clap::{Arg, ArgMatches, Command};
use platoon::core::method::kind::MethodKind;
use platoon::core::method::registry;
use platoon::core::method::settings::Settings;
use platoon::core::Method;

use crate::value_arg::{given, of_kind};

/// The method chosen and every setting given on the command line, of any method.
#[derive(Debug)]
pub struct MethodArgs {
    pub method: &'static dyn MethodKind,
    /// Each method's settings given, with the flags that gave them.
    given: Vec<(&'static dyn MethodKind, Settings, Vec<&'static str>)>,
}

impl MethodArgs {
    /// The method with its options; refuses one method's flags given to another.
    pub fn method(&self) -> Result<Method> {
        for (kind, _, flags) in &self.given {
            if kind.name() != self.method.name() && !flags.is_empty() {
                bail!(
                    "--{} sets {}: add --method {}",
                    flags.join(", --"),
                    kind.title(),
                    kind.name()
                );
            }
        }
        let given = self
            .given
            .iter()
            .find(|(k, _, _)| k.name() == self.method.name())
            .map(|(_, s, _)| s.clone())
            .unwrap_or_default();
        self.method
            .build(&given)
            .map_err(|e| match self.method.split_setting(&e) {
                Some((setting, problem)) => anyhow::anyhow!("--{}: {problem}", setting.flag),
                None => anyhow::Error::msg(e),
            })
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
        registry::all().into_iter().fold(cmd, |cmd, kind| {
            kind.settings().iter().fold(cmd, |cmd, s| {
                let help = format!("{}: {}", kind.title(), s.help);
                cmd.arg(of_kind(Arg::new(s.flag).long(s.flag).help(help), s.kind))
            })
        })
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
        let given = registry::all()
            .into_iter()
            .map(|kind| {
                let mut settings = Settings::default();
                let mut flags = Vec::new();
                for s in kind.settings() {
                    if let Some(v) = given(m, s.flag, s.kind) {
                        settings.set(s.key, v);
                        flags.push(s.flag);
                    }
                }
                (kind, settings, flags)
            })
            .collect();
        Ok(MethodArgs { method, given })
    }

    fn update_from_arg_matches(&mut self, m: &ArgMatches) -> Result<(), clap::Error> {
        *self = Self::from_arg_matches(m)?;
        Ok(())
    }
}
