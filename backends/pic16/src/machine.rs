//! The `pic16f876a` target's [`Machine`]: the compiled program running on plcc's
//! simulator of the chip, scan by scan (from the scan loop's top to `plc_scan_end`).

use crate::runtime::PinBinding;
use crate::sim::{Pic16, Port};
use crate::Build;
use plcc_ir::machine::{Machine, MachineError};
use plcc_ir::value::PlcValue;
use plcc_ir::{Module, Type};

/// Cycles cold start may take before the first scan.
const START_BUDGET: u64 = 50_000_000;
/// Cycles one scan may take (10 s of the real chip at 20 MHz).
pub const SCAN_BUDGET: u64 = 50_000_000;

/// A program running on the simulated chip.
pub struct PicMachine {
    module: Module,
    build: Build,
    sim: Pic16,
    clock_us: i64,
    started: bool,
}

impl PicMachine {
    /// A machine for a build of `module`.
    pub fn new(module: &Module, build: Build) -> PicMachine {
        let sim = Pic16::new(&build.image.words);
        PicMachine {
            module: module.clone(),
            build,
            sim,
            clock_us: 0,
            started: false,
        }
    }

    /// The build it runs.
    pub fn build(&self) -> &Build {
        &self.build
    }

    /// The simulator (for cycle counts and raw memory).
    pub fn sim(&self) -> &Pic16 {
        &self.sim
    }

    /// Cold start, then `scans` scans with the clock left to the chip's own timer
    /// (as on the hardware, and as gpsim runs it): the cycle count at the end of each.
    pub fn run_free(&mut self, scans: u32) -> Result<Vec<u64>, MachineError> {
        self.cold_start()?;
        let end = self.build.scan_end_addr;
        let mut at = Vec::new();
        for _ in 0..scans {
            let stop = self
                .sim
                .run_until(&[end], SCAN_BUDGET)
                .map_err(|e| MachineError(format!("pic16f876a: {e}")))?;
            if stop != crate::sim::Stop::Breakpoint(end) {
                return Err(MachineError("pic16f876a: a scan did not end".into()));
            }
            at.push(self.sim.cycles());
        }
        Ok(at)
    }

    fn locate(&self, path: &str) -> Result<(u16, Type, plcc_ir::ElemType, u8), MachineError> {
        let v = plcc_ir::vars::resolve(&self.module, path)?;
        let place = self.build.layout.place_of(&v.steps);
        let addr = self.build.data.addr(v.root, place.offset);
        Ok((addr, v.ty, v.elem, place.bit))
    }

    fn input_pin(&self, path: &str) -> Option<&PinBinding> {
        let canon = plcc_ir::vars::resolve(&self.module, path).ok()?.path;
        self.build
            .pins
            .iter()
            .find(|p| p.input && p.path.eq_ignore_ascii_case(&canon))
    }

    fn set_clock_in_ram(&mut self) {
        let ms = (self.clock_us.div_euclid(1000)) as u32;
        for k in 0..4 {
            self.sim
                .write(self.build.rt.clk_ms + k, (ms >> (8 * k)) as u8);
        }
        if let Some(ns) = self.build.rt.clk_ns {
            let v = self.clock_us.wrapping_mul(1000) as u64;
            for k in 0..8 {
                self.sim.write(ns + k, (v >> (8 * k)) as u8);
            }
        }
        // Restart the millisecond so no tick lands before the clock is sampled.
        self.sim.write(crate::isa::reg::TMR1L, 0);
        self.sim.write(crate::isa::reg::TMR1H, 0);
        let pir = self.sim.read(crate::isa::reg::PIR1);
        self.sim
            .write(crate::isa::reg::PIR1, pir & !(1 << crate::isa::reg::CCP1IF));
    }
}

fn port_of(reg: u16) -> Port {
    match reg {
        crate::isa::reg::PORTA => Port::A,
        crate::isa::reg::PORTB => Port::B,
        _ => Port::C,
    }
}

impl Machine for PicMachine {
    fn target(&self) -> &str {
        "pic16f876a"
    }

    fn vars_module(&self) -> &plcc_ir::Module {
        &self.module
    }

    fn cold_start(&mut self) -> Result<(), MachineError> {
        self.sim = Pic16::new(&self.build.image.words);
        // Garbage in RAM, as on the chip: a variable the program forgets to
        // initialise shows up as a difference from the other machines.
        self.sim.fill_ram(0xA5);
        self.sim.reset();
        self.clock_us = 0;
        let stop = self
            .sim
            .run_until(&[self.build.scan_addr], START_BUDGET)
            .map_err(|e| MachineError(format!("pic16f876a: {e}")))?;
        if stop != crate::sim::Stop::Breakpoint(self.build.scan_addr) {
            return Err(MachineError(format!(
                "pic16f876a: cold start did not reach the scan loop within {START_BUDGET} cycles"
            )));
        }
        self.started = true;
        Ok(())
    }

    fn set_clock_us(&mut self, us: i64) {
        self.clock_us = us;
    }

    fn scan(&mut self) -> Result<(), MachineError> {
        if !self.started {
            self.cold_start()?;
        }
        self.set_clock_in_ram();
        let end = self.build.scan_end_addr;
        let stop = self
            .sim
            .run_until(&[end], SCAN_BUDGET)
            .map_err(|e| MachineError(format!("pic16f876a: {e}")))?;
        if stop != crate::sim::Stop::Breakpoint(end) {
            return Err(MachineError(format!(
                "pic16f876a: the scan did not end within {SCAN_BUDGET} cycles (10 s at 20 MHz)"
            )));
        }
        Ok(())
    }

    fn read(&self, path: &str) -> Result<PlcValue, MachineError> {
        let (addr, ty, elem, bit) = self.locate(path)?;
        if ty == Type::I1 {
            return Ok(PlcValue::from_bool(self.sim.read(addr) >> bit & 1 != 0));
        }
        let n = crate::ram::scalar_bytes(ty) as u16;
        let mut bits = 0u64;
        for k in 0..n {
            bits |= (self.sim.read(addr + k) as u64) << (8 * k);
        }
        Ok(PlcValue::from_bits(elem, bits))
    }

    fn write(&mut self, path: &str, value: PlcValue) -> Result<(), MachineError> {
        let (addr, ty, elem, bit) = self.locate(path)?;
        if value.ty != elem {
            return Err(MachineError(format!(
                "`{path}` is {elem}, cannot write a {} value",
                value.ty
            )));
        }
        if let Some(p) = self.input_pin(path) {
            // Located inputs are latched from their pin at the start of each scan.
            let (port, b) = (port_of(p.pin.port), p.pin.bit);
            self.sim.set_input(port, b, value.bits != 0);
            return Ok(());
        }
        if ty == Type::I1 {
            let old = self.sim.read(addr);
            let new = if value.bits != 0 {
                old | 1 << bit
            } else {
                old & !(1 << bit)
            };
            self.sim.write(addr, new);
            return Ok(());
        }
        let n = crate::ram::scalar_bytes(ty) as u16;
        for k in 0..n {
            self.sim.write(addr + k, (value.bits >> (8 * k)) as u8);
        }
        Ok(())
    }

    fn fault(&self) -> bool {
        self.sim.read(self.build.rt.flags) >> crate::runtime::FAULT_BIT & 1 != 0
    }

    fn clear_fault(&mut self) {
        let f = self.sim.read(self.build.rt.flags);
        self.sim
            .write(self.build.rt.flags, f & !(1 << crate::runtime::FAULT_BIT));
    }
}
