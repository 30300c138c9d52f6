//! The Modbus TCP server: tokio-modbus's, on a thread and a single-threaded runtime
//! of its own, serving the I/O image ([`super::image`]) to any number of clients.
//!
//! Function codes 1 (read coils), 2 (read discrete inputs), 3 (read holding
//! registers), 4 (read input registers), 5 (write one coil), 6 (write one register),
//! 15 (write coils) and 16 (write registers). Any other function code gets the
//! exception "illegal function", an address outside a table "illegal data
//! address", a quantity the protocol does not allow "illegal data value"; nothing is
//! written then. A frame that cannot be decoded closes its connection (the other
//! clients and the scans go on).

use super::image::{Image, BITS, HOLDING_REGS, INPUT_REGS};
use super::Shared;
use std::net::SocketAddr;
use std::sync::Arc;
use tokio_modbus::{ExceptionCode, Request, Response};

/// The largest quantities one request may read or write (Modbus application
/// protocol v1.1b3).
const MAX_READ_BITS: usize = 2000;
const MAX_READ_REGS: usize = 125;
const MAX_WRITE_BITS: usize = 1968;
const MAX_WRITE_REGS: usize = 123;

/// Checks that `qty` items from `addr` are allowed (`1..=max`) and inside a table of
/// `len`; the range as indexes.
fn range(
    addr: u16,
    qty: usize,
    max: usize,
    len: usize,
) -> Result<std::ops::Range<usize>, ExceptionCode> {
    if qty == 0 || qty > max {
        return Err(ExceptionCode::IllegalDataValue);
    }
    let start = addr as usize;
    if start + qty > len {
        return Err(ExceptionCode::IllegalDataAddress);
    }
    Ok(start..start + qty)
}

/// Answers one request against the image (the caller holds its lock).
pub fn answer(img: &mut Image, req: Request<'_>) -> Result<Response, ExceptionCode> {
    match req {
        Request::ReadCoils(a, n) => {
            let r = range(a, n as usize, MAX_READ_BITS, BITS)?;
            Ok(Response::ReadCoils(img.coils[r].to_vec()))
        }
        Request::ReadDiscreteInputs(a, n) => {
            let r = range(a, n as usize, MAX_READ_BITS, BITS)?;
            Ok(Response::ReadDiscreteInputs(img.discrete[r].to_vec()))
        }
        Request::ReadHoldingRegisters(a, n) => {
            let r = range(a, n as usize, MAX_READ_REGS, HOLDING_REGS)?;
            Ok(Response::ReadHoldingRegisters(img.holding[r].to_vec()))
        }
        Request::ReadInputRegisters(a, n) => {
            let r = range(a, n as usize, MAX_READ_REGS, INPUT_REGS)?;
            Ok(Response::ReadInputRegisters(img.input_regs[r].to_vec()))
        }
        Request::WriteSingleCoil(a, v) => {
            let r = range(a, 1, 1, BITS)?;
            img.write_coils(r.start, &[v]);
            Ok(Response::WriteSingleCoil(a, v))
        }
        Request::WriteMultipleCoils(a, vs) => {
            let r = range(a, vs.len(), MAX_WRITE_BITS, BITS)?;
            img.write_coils(r.start, &vs);
            Ok(Response::WriteMultipleCoils(a, vs.len() as u16))
        }
        Request::WriteSingleRegister(a, v) => {
            let r = range(a, 1, 1, HOLDING_REGS)?;
            img.write_holding(r.start, &[v]);
            Ok(Response::WriteSingleRegister(a, v))
        }
        Request::WriteMultipleRegisters(a, vs) => {
            let r = range(a, vs.len(), MAX_WRITE_REGS, HOLDING_REGS)?;
            img.write_holding(r.start, &vs);
            Ok(Response::WriteMultipleRegisters(a, vs.len() as u16))
        }
        _ => Err(ExceptionCode::IllegalFunction),
    }
}

/// One client's service: every request answered under the image's lock.
struct PlcService {
    shared: Arc<Shared>,
}

impl tokio_modbus::server::Service for PlcService {
    type Request = Request<'static>;
    type Response = Response;
    type Exception = ExceptionCode;
    type Future = std::future::Ready<Result<Response, ExceptionCode>>;

    fn call(&self, req: Self::Request) -> Self::Future {
        std::future::ready(answer(&mut self.shared.lock_image(), req))
    }
}

/// Binds `addr` and serves the image on a thread of its own; the address bound (the
/// port the system chose for port 0).
pub fn start(addr: SocketAddr, shared: Arc<Shared>) -> std::io::Result<SocketAddr> {
    let listener = std::net::TcpListener::bind(addr)?;
    listener.set_nonblocking(true)?;
    let bound = listener.local_addr()?;
    let runtime = tokio::runtime::Builder::new_current_thread()
        .enable_io()
        .build()?;
    std::thread::Builder::new()
        .name("modbus".into())
        .spawn(move || {
            runtime.block_on(async move {
                let listener = match tokio::net::TcpListener::from_std(listener) {
                    Ok(l) => l,
                    Err(e) => {
                        eprintln!("error: modbus: {e}");
                        return;
                    }
                };
                let server = tokio_modbus::server::tcp::Server::new(listener);
                let on_connected = |stream, peer| {
                    let shared = Arc::clone(&shared);
                    async move {
                        tokio_modbus::server::tcp::accept_tcp_connection(stream, peer, |_| {
                            Ok(Some(PlcService {
                                shared: Arc::clone(&shared),
                            }))
                        })
                    }
                };
                // A connection whose frames cannot be decoded is closed; the server
                // goes on.
                if let Err(e) = server.serve(&on_connected, |_err| {}).await {
                    eprintln!("error: modbus: {e}");
                }
            })
        })?;
    Ok(bound)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::borrow::Cow;

    #[test]
    fn requests_against_the_image() {
        let mut img = Image::default();
        let ok = |r: Result<Response, ExceptionCode>| r.expect("answered");
        ok(answer(&mut img, Request::WriteSingleCoil(9, true)));
        assert_eq!(
            ok(answer(&mut img, Request::ReadCoils(8, 3))),
            Response::ReadCoils(vec![false, true, false])
        );
        ok(answer(
            &mut img,
            Request::WriteMultipleRegisters(4096, Cow::Owned(vec![1, 2, 3, 4])),
        ));
        assert_eq!(
            ok(answer(&mut img, Request::ReadHoldingRegisters(4097, 2))),
            Response::ReadHoldingRegisters(vec![2, 3])
        );
        let err = |r: Result<Response, ExceptionCode>| r.expect_err("refused");
        assert_eq!(
            err(answer(&mut img, Request::ReadCoils(8191, 2))),
            ExceptionCode::IllegalDataAddress
        );
        assert_eq!(
            err(answer(&mut img, Request::ReadInputRegisters(1024, 1))),
            ExceptionCode::IllegalDataAddress
        );
        assert_eq!(
            err(answer(&mut img, Request::ReadHoldingRegisters(0, 126))),
            ExceptionCode::IllegalDataValue
        );
        assert_eq!(
            err(answer(&mut img, Request::ReadCoils(0, 0))),
            ExceptionCode::IllegalDataValue
        );
        assert_eq!(
            err(answer(
                &mut img,
                Request::WriteMultipleRegisters(8190, Cow::Owned(vec![9, 9, 9]))
            )),
            ExceptionCode::IllegalDataAddress
        );
        assert_eq!(
            err(answer(&mut img, Request::MaskWriteRegister(0, 0, 0))),
            ExceptionCode::IllegalFunction
        );
        // Nothing refused was written.
        assert_eq!(img.holding[8190..], [0, 0]);
    }
}
