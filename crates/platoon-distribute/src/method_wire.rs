//! A frame's method on the wire: its name, every setting by key (`MethodKind::settings_of`) and
//! its state beyond them as the method encodes it (`MethodKind::state_bytes`: the path tracer's
//! world cache and reservoirs), rebuilt on the receiving rank through the same registry, so this
//! names no method. A method whose preparation cannot travel says so itself
//! (`MethodKind::travels`).

use super::wire::{Reader, WireError, Writer};
use platoon_core::method::registry::{kind, KINDS};
use platoon_core::method::settings::{Settings, Value};
use platoon_core::method::Method;

/// Whether `method`'s frames can be sent to another rank.
pub fn travels(method: &Method) -> Result<(), String> {
    method.kind().travels().map_err(|why| {
        let movable: Vec<&str> = KINDS
            .iter()
            .filter(|k| k.travels().is_ok())
            .map(|k| k.name())
            .collect();
        format!(
            "{} cannot render over the ranks of a game loop yet ({why}): use --method {}",
            method.kind().name(),
            movable.join(" or ")
        )
    })
}

pub fn put_method(w: &mut Writer, method: &Method) -> Result<(), String> {
    travels(method)?;
    let settings = method.settings();
    w.str(method.kind().name());
    w.u32(settings.0.len() as u32);
    for (key, value) in &settings.0 {
        w.str(key);
        match value {
            Value::Count(n) => {
                w.u8(0);
                w.u32(*n);
            }
            Value::Number(v) => {
                w.u8(1);
                w.f32(*v);
            }
            Value::Switch(on) => {
                w.u8(2);
                w.u8(*on as u8);
            }
            Value::Tile(t) => {
                w.u8(3);
                w.pod(t);
            }
            Value::Word(s) => {
                w.u8(4);
                w.str(s);
            }
        }
    }
    match method.kind().state_bytes(method)? {
        Some(state) => {
            w.flag(true);
            w.bytes(&state);
        }
        None => w.flag(false),
    }
    Ok(())
}

pub fn get_method(r: &mut Reader) -> Result<Method, WireError> {
    let name = r.string()?;
    let kind = kind(&name).ok_or_else(|| WireError(format!("unknown method {name:?}")))?;
    let mut settings = Settings::default();
    for _ in 0..r.u32()? {
        let key = r.string()?;
        let setting = kind
            .setting(&key)
            .ok_or_else(|| WireError(format!("{name} has no setting {key:?}")))?;
        let value = match r.u8()? {
            0 => Value::Count(r.u32()?),
            1 => Value::Number(r.f32()?),
            2 => Value::Switch(r.u8()? != 0),
            3 => Value::Tile(
                r.pod::<u32>()?
                    .try_into()
                    .map_err(|_| WireError(format!("{name}'s {key}")))?,
            ),
            4 => Value::Word(r.string()?),
            t => return Err(WireError(format!("{name}'s {key}: unknown value kind {t}"))),
        };
        settings.set(setting.key, value);
    }
    let method = kind
        .build(&settings)
        .map_err(|e| WireError(format!("{name}: {e}")))?;
    match r.flag()? {
        true => kind
            .with_state(method, r.bytes()?)
            .map_err(|e| WireError(format!("{name}: {e}"))),
        false => Ok(method),
    }
}
