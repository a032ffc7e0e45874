//! The companion's parameters as one set: those of a `--params` file (the autopilots' .parm
//! form) and of `--param`, each checked alone, then set together so that the order they are
//! written in does not matter; a refusal names every value it refuses.

use twocars::mavlink::params::{index, Params, Refusal, SPECS};
use twocars::mavlink::Endpoint;

/// The (name, value) pairs of a .parm file: `NAME VALUE` or `NAME,VALUE` a line, blank lines
/// and `#` comments skipped.
///
/// # Errors
/// The first line that is neither, by its number.
pub fn parse_parm(text: &str) -> Result<Vec<(String, f32)>, String> {
    let mut out = Vec::new();
    for (number, line) in text.lines().enumerate() {
        let line = line.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let mut fields = line
            .split(|c: char| c == ',' || c.is_whitespace())
            .filter(|f| !f.is_empty());
        let pair = match (fields.next(), fields.next(), fields.next()) {
            (Some(name), Some(value), None) => value.parse::<f32>().ok().map(|v| (name, v)),
            _ => None,
        };
        let (name, value) = pair.ok_or(format!("line {}: not NAME VALUE: {line}", number + 1))?;
        out.push((name.to_string(), value));
    }
    Ok(out)
}

/// The parameters a set-wide refusal is about.
fn involved(refusal: Refusal) -> &'static [usize] {
    match refusal {
        Refusal::LagBeyondTimeout => &[index::TGT_LAG, index::LEAD, index::TIMEOUT],
        _ => &[index::V_PM, index::W_PM, index::V_EM, index::W_EM],
    }
}

/// Sets `given` (name, value; a later value of a name over an earlier one) on `endpoint` as
/// one set.
///
/// # Errors
/// Every unknown name and every value out of range, one a line; or the set's refusal with the
/// values it is about. The endpoint is then unchanged.
pub fn set(endpoint: &mut Endpoint, given: &[(String, f32)]) -> Result<(), String> {
    let mut values = Vec::new();
    let mut wrong = Vec::new();
    for (name, value) in given {
        match Params::find(name.as_bytes()) {
            None => wrong.push(format!("{name} = {value}: {}", Refusal::UnknownName.text())),
            Some(i) => match Params::admissible(i, *value) {
                Ok(()) => values.push((i, *value)),
                Err(refusal) => wrong.push(format!("{name} = {value}: {}", refusal.text())),
            },
        }
    }
    if !wrong.is_empty() {
        return Err(wrong.join("\n"));
    }
    endpoint.set_params(&values).map_err(|(_, refusal)| {
        let params = endpoint.params();
        let named: Vec<String> = involved(refusal)
            .iter()
            .filter_map(|&i| {
                let given = values.iter().rev().find(|(j, _)| *j == i).map(|&(_, v)| v);
                let value = given.or_else(|| params.get(i))?;
                Some(format!("{} = {value}", SPECS.get(i)?.name))
            })
            .collect();
        format!("{}: {}", named.join(", "), refusal.text())
    })
}

/// Every parameter as set, `NAME VALUE` a line (the .parm form `--params` reads).
pub fn listing(params: &Params) -> String {
    SPECS
        .iter()
        .enumerate()
        .filter_map(|(i, spec)| Some(format!("{} {}\n", spec.name, params.get(i)?)))
        .collect()
}
