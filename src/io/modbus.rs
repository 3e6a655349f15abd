//! The Modbus TCP client [`Device`]: tokio-modbus's synchronous client (a current-thread
//! runtime of its own, so the update thread never waits on another thread), every request and
//! every connection attempt bounded by the map's timeout.
//!
//! A request that fails on the transport (refused, reset, closed, timed out, or an answer that
//! does not match the request) drops the connection: the next [`Device::connect`] opens a new
//! one, so a late answer to a timed-out request can never be taken for the answer to a later
//! one. An exception answer keeps the connection: the device is there, it refused the request.

use super::map::Table;
use super::memory::Device;
use super::target::{host_for_port, modbus_device};
use super::IoFault;
use std::net::{SocketAddr, ToSocketAddrs};
use std::time::Duration;
use tokio_modbus::client::sync::{self, Reader as _, Writer as _};
use tokio_modbus::Slave;

/// A Modbus TCP coupler at `host:port`, unit `unit`.
pub struct ModbusTcp {
    host: String,
    port: u16,
    unit: u8,
    timeout: Duration,
    ctx: Option<sync::Context>,
}

impl std::fmt::Debug for ModbusTcp {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ModbusTcp")
            .field("device", &self.device())
            .field("connected", &self.ctx.is_some())
            .finish()
    }
}

impl ModbusTcp {
    /// A client for the coupler; nothing is opened until [`Device::connect`].
    pub fn new(host: &str, port: u16, unit: u8, timeout_ns: u64) -> ModbusTcp {
        ModbusTcp {
            host: host.to_string(),
            port,
            unit,
            timeout: Duration::from_nanos(timeout_ns),
            ctx: None,
        }
    }

    fn address(&self) -> Result<SocketAddr, IoFault> {
        let text = format!("{}:{}", host_for_port(&self.host), self.port);
        let mut addrs = text.to_socket_addrs().map_err(|e| IoFault::Disconnected {
            device: self.device(),
            cause: format!("cannot resolve {}: {e}", self.host),
        })?;
        addrs.next().ok_or_else(|| IoFault::Disconnected {
            device: self.device(),
            cause: format!("{} resolves to no address", self.host),
        })
    }

    fn timeout_ms(&self) -> u64 {
        u64::try_from(self.timeout.as_millis()).unwrap_or(u64::MAX)
    }

    /// The fault for a failed request; transport failures drop the connection.
    fn fault(&mut self, request: String, e: tokio_modbus::Error) -> IoFault {
        self.ctx = None;
        match e {
            tokio_modbus::Error::Transport(io) if io.kind() == std::io::ErrorKind::TimedOut => {
                IoFault::Timeout {
                    device: self.device(),
                    request,
                    timeout_ms: self.timeout_ms(),
                }
            }
            tokio_modbus::Error::Transport(io) => IoFault::Disconnected {
                device: self.device(),
                cause: format!("{request}: {}", transport_words(&io, self.timeout_ms())),
            },
            tokio_modbus::Error::Protocol(p) => IoFault::Disconnected {
                device: self.device(),
                cause: format!("{request}: {}", protocol_words(&p)),
            },
        }
    }

    /// Run one request on the open connection, mapping every failure to its fault.
    fn call<T>(
        &mut self,
        request: impl Fn() -> String,
        f: impl FnOnce(&mut sync::Context) -> tokio_modbus::Result<T>,
    ) -> Result<T, IoFault> {
        let Some(ctx) = self.ctx.as_mut() else {
            return Err(IoFault::Disconnected {
                device: self.device(),
                cause: "no connection".into(),
            });
        };
        match f(ctx) {
            Ok(Ok(v)) => Ok(v),
            Ok(Err(code)) => Err(IoFault::Exception {
                device: self.device(),
                request: request(),
                code: u8::from(code),
            }),
            Err(e) => Err(self.fault(request(), e)),
        }
    }
}

/// A transport failure in the operator's words: what happened on the wire, never an `errno`
/// of a non-blocking socket.
fn transport_words(e: &std::io::Error, timeout_ms: u64) -> String {
    use std::io::ErrorKind as K;
    // EINPROGRESS / EALREADY / EAGAIN: a non-blocking connect or request that had not
    // completed when its time ran out.
    let unfinished = matches!(e.raw_os_error(), Some(11 | 114 | 115));
    match e.kind() {
        K::UnexpectedEof | K::ConnectionReset | K::BrokenPipe | K::ConnectionAborted => {
            "the coupler closed the connection".into()
        }
        K::ConnectionRefused => "the coupler refused the connection".into(),
        K::TimedOut | K::WouldBlock => format!("no answer within {timeout_ms} ms"),
        _ if unfinished => format!("no answer within {timeout_ms} ms"),
        K::NotConnected => "the connection is closed".into(),
        K::HostUnreachable | K::NetworkUnreachable => {
            "the coupler cannot be reached (no route on the network)".into()
        }
        K::AddrNotAvailable => "the coupler's address is not available on this machine".into(),
        K::InvalidData => "an answer that is not Modbus TCP".into(),
        _ => {
            // The system's own words, without the `(os error N)` suffix.
            let text = e.to_string();
            match text.find(" (os error") {
                Some(at) => text[..at].to_string(),
                None => text,
            }
        }
    }
}

/// An answer that does not belong to the request, in words: tokio-modbus says which headers
/// differ in a debug print, from which the transaction and unit ids are taken.
fn protocol_words(p: &tokio_modbus::ProtocolError) -> String {
    match p {
        tokio_modbus::ProtocolError::HeaderMismatch { message, .. } => {
            let ids = |key: &str| -> Vec<u64> {
                message
                    .match_indices(key)
                    .filter_map(|(at, _)| {
                        let rest = &message[at + key.len()..];
                        let digits: String =
                            rest.chars().take_while(char::is_ascii_digit).collect();
                        digits.parse().ok()
                    })
                    .collect()
            };
            let (transactions, units) = (ids("transaction_id: "), ids("unit_id: "));
            match (transactions.as_slice(), units.as_slice()) {
                (&[expected, got], _) if expected != got => {
                    format!("answer for another request (transaction {got}, expected {expected})")
                }
                (_, &[expected, got]) if expected != got => {
                    format!("answer from another unit (unit {got}, expected {expected})")
                }
                _ => "an answer that does not match the request".into(),
            }
        }
        tokio_modbus::ProtocolError::FunctionCodeMismatch { request, result } => {
            let got = match result {
                Ok(response) => response.function_code().value(),
                Err(exception) => exception.function.value(),
            };
            format!(
                "answer to another function (function {got}, expected {})",
                request.value()
            )
        }
    }
}

/// `read discrete_input 0..10`, for fault messages.
fn describe(op: &str, table: Table, start: u16, count: usize) -> String {
    let end = usize::from(start) + count;
    format!("{op} {} {start}..{end}", table.name())
}

impl Device for ModbusTcp {
    fn device(&self) -> String {
        modbus_device(&self.host, self.port, self.unit)
    }

    fn connect(&mut self) -> Result<(), IoFault> {
        self.ctx = None;
        let addr = self.address()?;
        match sync::tcp::connect_slave_with_timeout(addr, Slave(self.unit), Some(self.timeout)) {
            Ok(ctx) => {
                self.ctx = Some(ctx);
                Ok(())
            }
            Err(e) if e.kind() == std::io::ErrorKind::TimedOut => Err(IoFault::Timeout {
                device: self.device(),
                request: "connect".into(),
                timeout_ms: self.timeout_ms(),
            }),
            Err(e) => Err(IoFault::Disconnected {
                device: self.device(),
                cause: format!(
                    "connect: {}",
                    match e.kind() {
                        std::io::ErrorKind::ConnectionRefused => format!(
                            "the coupler refused the connection (nothing listens on {}:{})",
                            self.host, self.port
                        ),
                        _ => transport_words(&e, self.timeout_ms()),
                    }
                ),
            }),
        }
    }

    fn read_bits(&mut self, table: Table, start: u16, count: u16) -> Result<Vec<bool>, IoFault> {
        let request = || describe("read", table, start, count.into());
        let mut bits = if table == Table::Coil {
            self.call(request, |c| c.read_coils(start, count))?
        } else {
            self.call(request, |c| c.read_discrete_inputs(start, count))?
        };
        // The answer carries whole bytes: the bits past `count` are padding.
        if bits.len() < usize::from(count) {
            return Err(self.short_answer(request(), count.into(), bits.len()));
        }
        bits.truncate(count.into());
        Ok(bits)
    }

    fn read_registers(
        &mut self,
        table: Table,
        start: u16,
        count: u16,
    ) -> Result<Vec<u16>, IoFault> {
        let request = || describe("read", table, start, count.into());
        let words = if table == Table::HoldingRegister {
            self.call(request, |c| c.read_holding_registers(start, count))?
        } else {
            self.call(request, |c| c.read_input_registers(start, count))?
        };
        if words.len() != usize::from(count) {
            return Err(self.short_answer(request(), count.into(), words.len()));
        }
        Ok(words)
    }

    fn write_coils(&mut self, start: u16, bits: &[bool]) -> Result<(), IoFault> {
        let request = || describe("write", Table::Coil, start, bits.len());
        self.call(request, |c| c.write_multiple_coils(start, bits))
    }

    fn write_registers(&mut self, start: u16, words: &[u16]) -> Result<(), IoFault> {
        let request = || describe("write", Table::HoldingRegister, start, words.len());
        self.call(request, |c| c.write_multiple_registers(start, words))
    }
}

impl ModbusTcp {
    /// A device that answered with fewer points than asked: a broken device or gateway; the
    /// connection is dropped like any other protocol error.
    fn short_answer(&mut self, request: String, asked: usize, got: usize) -> IoFault {
        self.ctx = None;
        IoFault::Disconnected {
            device: self.device(),
            cause: format!("{request}: answered {got} points where {asked} were asked"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::{Error, ErrorKind};

    #[test]
    fn transport_failures_are_said_in_words() {
        let said = |e: Error| transport_words(&e, 50);
        assert_eq!(
            said(Error::from(ErrorKind::UnexpectedEof)),
            "the coupler closed the connection"
        );
        assert_eq!(
            said(Error::from(ErrorKind::ConnectionReset)),
            "the coupler closed the connection"
        );
        assert_eq!(
            said(Error::from_raw_os_error(115)),
            "no answer within 50 ms"
        );
        assert_eq!(
            said(Error::from(ErrorKind::TimedOut)),
            "no answer within 50 ms"
        );
        assert!(!said(Error::from_raw_os_error(28)).contains("os error"));
    }

    #[test]
    fn an_answer_to_another_request_names_both_transactions() {
        let p = tokio_modbus::ProtocolError::HeaderMismatch {
            message: "expected/request = Header { transaction_id: 17, unit_id: 1 }, actual/response = Header { transaction_id: 19, unit_id: 1 }".into(),
            result: Ok(tokio_modbus::Response::ReadCoils(vec![true])),
        };
        assert_eq!(
            protocol_words(&p),
            "answer for another request (transaction 19, expected 17)"
        );
        let p = tokio_modbus::ProtocolError::HeaderMismatch {
            message: "expected/request = Header { transaction_id: 4, unit_id: 1 }, actual/response = Header { transaction_id: 4, unit_id: 3 }".into(),
            result: Ok(tokio_modbus::Response::ReadCoils(vec![true])),
        };
        assert_eq!(
            protocol_words(&p),
            "answer from another unit (unit 3, expected 1)"
        );
    }
}
