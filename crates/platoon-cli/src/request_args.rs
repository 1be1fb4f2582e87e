//! The request's frame options as flags (`--spp`, `--filter`, `--max-depth`...), made from the
//! facade's table (`platoon::request::options::OPTIONS`), so this file names no option: a
//! value is parsed by its kind and set on the request by the table's own rule. A command takes
//! the whole table (`render`) or the part that applies to it (`view`'s live frames), from its
//! own base request (whose values help shows as the defaults).

use anyhow::{anyhow, Result};
use clap::{Arg, ArgMatches, Command};
use platoon::core::method::settings::{Value, ValueKind};
use platoon::request::options::{default_text, RequestOption, OPTIONS};
use platoon::Request;

use crate::value_arg::{given, of_kind};

/// Which of the table's options a command takes, and the request they are given on.
pub trait Selection {
    /// The keys it takes; None: every option.
    const KEYS: Option<&'static [&'static str]>;
    /// The request the command starts from: what an option not given keeps.
    fn base() -> Request;
}

/// `platoon render`: every option, from the default request.
#[derive(Debug)]
pub struct Still;

impl Selection for Still {
    const KEYS: Option<&'static [&'static str]> = None;
    fn base() -> Request {
        Request::default()
    }
}

/// `platoon view`: what a live view's frames take (one sample a frame, its own size, every
/// device by default).
#[derive(Debug)]
pub struct Live;

impl Selection for Live {
    const KEYS: Option<&'static [&'static str]> = Some(&[
        "max_depth",
        "seed",
        "filter",
        "devices",
        "balancer",
        "validation",
        "traversal",
    ]);
    fn base() -> Request {
        Request {
            spp: 1,
            devices: platoon::devices::DeviceSpec::All,
            ..Request::default()
        }
    }
}

fn taken<S: Selection>() -> impl Iterator<Item = &'static RequestOption> {
    OPTIONS
        .iter()
        .filter(|o| S::KEYS.is_none_or(|keys| keys.contains(&o.key)))
}

/// The frame options given on the command line, in the table's order.
#[derive(Debug)]
pub struct RequestArgs<S: Selection = Still> {
    given: Vec<(&'static RequestOption, Value)>,
    selection: std::marker::PhantomData<S>,
}

impl<S: Selection> RequestArgs<S> {
    /// The command's base request with every option given set on it; an error names the flag.
    pub fn request(&self) -> Result<Request> {
        let mut request = S::base();
        self.apply(&mut request)?;
        Ok(request)
    }

    /// Sets every option given on `request`; an error names the flag.
    pub fn apply(&self, request: &mut Request) -> Result<()> {
        for (option, value) in &self.given {
            (option.set)(request, value).map_err(|e| anyhow!("--{}: {e}", option.flag))?;
        }
        Ok(())
    }
}

impl<S: Selection> clap::Args for RequestArgs<S> {
    fn augment_args(cmd: Command) -> Command {
        let base = S::base();
        taken::<S>().fold(cmd, |cmd, o| {
            let help = match default_text(o, &base).filter(|_| o.kind != ValueKind::Switch) {
                Some(d) => format!("{} [default: {d}]", o.help),
                None => o.help.to_string(),
            };
            let arg = Arg::new(o.key).long(o.flag).help(help);
            let arg = match o.kind {
                ValueKind::Switch => arg,
                _ => arg.value_name(o.key).allow_negative_numbers(true),
            };
            cmd.arg(of_kind(arg, o.kind))
        })
    }

    fn augment_args_for_update(cmd: Command) -> Command {
        Self::augment_args(cmd)
    }
}

impl<S: Selection> clap::FromArgMatches for RequestArgs<S> {
    fn from_arg_matches(m: &ArgMatches) -> Result<Self, clap::Error> {
        let given = taken::<S>()
            .filter_map(|o| given(m, o.key, o.kind).map(|v| (o, v)))
            .collect();
        Ok(RequestArgs {
            given,
            selection: std::marker::PhantomData,
        })
    }

    fn update_from_arg_matches(&mut self, m: &ArgMatches) -> Result<(), clap::Error> {
        *self = Self::from_arg_matches(m)?;
        Ok(())
    }
}
