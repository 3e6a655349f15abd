//! Which I/O a run uses: `--io sim` (the default), `--io modbus` (the coupler the machine
//! file names) or `--io modbus://HOST[:PORT][/UNIT]`.

use super::map::{DEFAULT_PORT, DEFAULT_UNIT};

/// The I/O a run is wired to.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum IoTarget {
    /// The simulated world of the scenario.
    Simulator,
    /// A Modbus TCP device.
    Modbus {
        /// Host name or address (IPv6 in brackets: `[::1]`); None: the machine file's.
        host: Option<String>,
        /// TCP port; None: the machine file's, else 502.
        port: Option<u16>,
        /// Unit id; None: the machine file's, else 1.
        unit: Option<u8>,
    },
}

impl IoTarget {
    /// Parse the `--io` argument.
    pub fn parse(text: &str) -> Result<IoTarget, String> {
        let t = text.trim();
        if t.eq_ignore_ascii_case("sim") || t.eq_ignore_ascii_case("simulator") {
            return Ok(IoTarget::Simulator);
        }
        if t.eq_ignore_ascii_case("modbus") {
            return Ok(IoTarget::Modbus {
                host: None,
                port: None,
                unit: None,
            });
        }
        let Some(rest) = t.strip_prefix("modbus://") else {
            return Err(format!(
                "`{text}` is not an I/O: use `sim`, `modbus` (the machine file's [modbus] host) or `modbus://HOST:PORT` (e.g. modbus://192.168.0.10:502)"
            ));
        };
        let (authority, unit) = match rest.split_once('/') {
            Some((a, "")) => (a, None),
            Some((a, u)) => (
                a,
                Some(
                    u.parse::<u8>()
                        .map_err(|_| format!("`{u}` is not a unit id (0 to 255)"))?,
                ),
            ),
            None => (rest, None),
        };
        let (host, port) = if let Some(v6) = authority.strip_prefix('[') {
            let (h, after) = v6
                .split_once(']')
                .ok_or_else(|| format!("`{authority}`: an IPv6 address needs its `]`"))?;
            (h, after.strip_prefix(':'))
        } else {
            match authority.rsplit_once(':') {
                Some((h, p)) => (h, Some(p)),
                None => (authority, None),
            }
        };
        if host.is_empty() || host.contains(char::is_whitespace) {
            return Err(format!("`{text}` names no host"));
        }
        let port = match port {
            None => None,
            Some(p) => match p.parse::<u16>() {
                Ok(0) | Err(_) => return Err(format!("`{p}` is not a TCP port (1 to 65535)")),
                Ok(n) => Some(n),
            },
        };
        Ok(IoTarget::Modbus {
            host: Some(host.to_string()),
            port,
            unit,
        })
    }

    /// The device as shown in messages, with the defaults filled in.
    pub fn describe(&self) -> String {
        match self {
            IoTarget::Simulator => "simulator".into(),
            IoTarget::Modbus { host, port, unit } => modbus_device(
                host.as_deref().unwrap_or("(the machine file's host)"),
                port.unwrap_or(DEFAULT_PORT),
                unit.unwrap_or(DEFAULT_UNIT),
            ),
        }
    }
}

/// A host as it stands before `:PORT`: an IPv6 address in brackets.
pub fn host_for_port(host: &str) -> String {
    if host.contains(':') {
        format!("[{host}]")
    } else {
        host.to_string()
    }
}

/// A Modbus TCP device as messages and the trace name it: `modbus://HOST:PORT unit N`.
pub fn modbus_device(host: &str, port: u16, unit: u8) -> String {
    format!("modbus://{}:{port} unit {unit}", host_for_port(host))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn modbus(host: &str, port: Option<u16>, unit: Option<u8>) -> IoTarget {
        IoTarget::Modbus {
            host: Some(host.into()),
            port,
            unit,
        }
    }

    #[test]
    fn targets() {
        assert_eq!(IoTarget::parse("sim"), Ok(IoTarget::Simulator));
        assert_eq!(
            IoTarget::parse("modbus"),
            Ok(IoTarget::Modbus {
                host: None,
                port: None,
                unit: None
            })
        );
        assert_eq!(
            IoTarget::parse("modbus://127.0.0.1:5020"),
            Ok(modbus("127.0.0.1", Some(5020), None))
        );
        assert_eq!(
            IoTarget::parse("modbus://coupler/3"),
            Ok(modbus("coupler", None, Some(3)))
        );
        assert_eq!(
            IoTarget::parse("modbus://[::1]:502/7"),
            Ok(modbus("::1", Some(502), Some(7)))
        );
        assert_eq!(
            modbus("::1", None, None).describe(),
            "modbus://[::1]:502 unit 1"
        );
    }

    #[test]
    fn bad_targets() {
        assert!(IoTarget::parse("tcp://x").is_err());
        assert!(IoTarget::parse("modbus://:502").is_err());
        assert!(IoTarget::parse("modbus://h:0").is_err());
        assert!(IoTarget::parse("modbus://h:70000").is_err());
        assert!(IoTarget::parse("modbus://h/256").is_err());
        assert!(IoTarget::parse("modbus://[::1:502").is_err());
    }
}
