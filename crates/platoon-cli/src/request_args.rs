//! The request's frame options as flags (`--spp`, `--filter`, `--max-depth`...), made from the
//! facade's table (`platoon::request::options::OPTIONS`), so this file names no option: a
//! value is parsed by its kind and set on the request by the table's own rule.

use anyhow::{anyhow, Result};
use clap::{Arg, ArgAction, ArgMatches, Command};
use platoon::core::method::settings::{Value, ValueKind};
use platoon::request::options::{default_text, RequestOption, OPTIONS};
use platoon::Request;

/// The frame options given on the command line, in the table's order.
#[derive(Debug)]
pub struct RequestArgs {
    given: Vec<(&'static RequestOption, Value)>,
}

impl RequestArgs {
    /// Sets every option given on `request`; an error names the flag.
    pub fn apply(&self, request: &mut Request) -> Result<()> {
        for (option, value) in &self.given {
            (option.set)(request, value).map_err(|e| anyhow!("--{}: {e}", option.flag))?;
        }
        Ok(())
    }
}

fn value_parser(kind: ValueKind) -> impl Fn(&str) -> Result<Value, String> + Clone {
    move |text: &str| Value::parse(kind, text)
}

impl clap::Args for RequestArgs {
    fn augment_args(cmd: Command) -> Command {
        OPTIONS.iter().fold(cmd, |cmd, o| {
            let help = match default_text(o).filter(|_| o.kind != ValueKind::Switch) {
                Some(d) => format!("{} [default: {d}]", o.help),
                None => o.help.to_string(),
            };
            let arg = Arg::new(o.key).long(o.flag).help(help);
            cmd.arg(match o.kind {
                ValueKind::Switch => arg.action(ArgAction::SetTrue),
                kind => arg
                    .value_name(o.key)
                    .allow_negative_numbers(true)
                    .value_parser(value_parser(kind)),
            })
        })
    }

    fn augment_args_for_update(cmd: Command) -> Command {
        Self::augment_args(cmd)
    }
}

impl clap::FromArgMatches for RequestArgs {
    fn from_arg_matches(m: &ArgMatches) -> Result<Self, clap::Error> {
        let given = OPTIONS
            .iter()
            .filter_map(|o| {
                let value = match o.kind {
                    ValueKind::Switch => m.get_flag(o.key).then_some(Value::Switch(true)),
                    _ => m.get_one::<Value>(o.key).cloned(),
                };
                value.map(|v| (o, v))
            })
            .collect();
        Ok(RequestArgs { given })
    }

    fn update_from_arg_matches(&mut self, m: &ArgMatches) -> Result<(), clap::Error> {
        *self = Self::from_arg_matches(m)?;
        Ok(())
    }
}
