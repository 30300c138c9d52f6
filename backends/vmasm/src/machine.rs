//! The `vmasm` target's [`Machine`]: the compiled XCP image running on plcc's VM.
//!
//! Cold start runs from code address 0 (the initialisers) up to the task body's
//! first instruction (`TSKLOOP`, the DCP's `BodyCodeAddres`); each scan then runs the
//! body up to TRML, with CUR_TIME fixed at the scan's clock. Data memory starts full
//! of garbage, as on a device: the program initialises what it reads.

use crate::build::Build;
use crate::vm::{End, Vm};
use plcc_ir::machine::{Machine, MachineError};
use plcc_ir::value::PlcValue;
use plcc_ir::{Module, Type};
use std::time::{Duration, Instant};

/// Instructions run between two looks at the watchdog.
const CHUNK: u64 = 1 << 22;
/// Instructions cold start may take.
const START_BUDGET: u64 = 1 << 32;

/// A program running on plcc's CPDev VM.
pub struct VmMachine {
    module: Module,
    build: Build,
    vm: Vm,
    clock_us: i64,
    started: bool,
    watchdog: Option<Duration>,
}

impl VmMachine {
    /// A machine for a build of `module`.
    pub fn new(module: &Module, build: Build) -> Result<VmMachine, String> {
        let vm = Vm::for_port(
            &build.image.code,
            build.data_size as usize,
            build.settings.mode,
            build.settings.port,
        )
        .map_err(|e| format!("vmasm: {e}"))?;
        Ok(VmMachine {
            module: module.clone(),
            build,
            vm,
            clock_us: 0,
            started: false,
            watchdog: None,
        })
    }

    /// The build it runs.
    pub fn build(&self) -> &Build {
        &self.build
    }

    /// The VM (for instruction counts and raw memory).
    pub fn vm(&self) -> &Vm {
        &self.vm
    }

    fn locate(&self, path: &str) -> Result<(usize, Type, plcc_ir::ElemType), MachineError> {
        let v = plcc_ir::vars::resolve(&self.module, path)?;
        let addr =
            self.build.data_addrs[v.root.index()] as u64 + self.build.layout.offset_of(&v.steps);
        Ok((addr as usize, v.ty, v.elem))
    }

    fn err(e: impl std::fmt::Display) -> MachineError {
        MachineError(format!("vmasm: {e}"))
    }
}

impl Machine for VmMachine {
    fn target(&self) -> &str {
        "vmasm"
    }

    fn vars_module(&self) -> &plcc_ir::Module {
        &self.module
    }

    fn cold_start(&mut self) -> Result<(), MachineError> {
        self.vm.reset();
        self.vm.data_mut().fill(0xA5);
        self.clock_us = 0;
        self.vm.set_clock_ms(0);
        let stop = self.build.loop_addr;
        match self
            .vm
            .run(Some(stop), START_BUDGET)
            .map_err(Self::err)?
            .end
        {
            End::StopAt => {}
            other => {
                return Err(MachineError(format!(
                    "vmasm: cold start did not reach the task body ({other:?})"
                )))
            }
        }
        self.vm.set_status(0);
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
        self.vm.set_clock_ms(self.clock_us.div_euclid(1000) as u32);
        let start = Instant::now();
        loop {
            match self.vm.run(None, CHUNK).map_err(Self::err)?.end {
                End::Trml => return Ok(()),
                End::Budget => {
                    if let Some(limit) = self.watchdog {
                        if start.elapsed() > limit {
                            return Err(MachineError(format!(
                                "vmasm: the scan ran longer than {} s (watchdog)",
                                limit.as_secs_f64()
                            )));
                        }
                    }
                }
                other => return Err(MachineError(format!("vmasm: the scan stopped ({other:?})"))),
            }
        }
    }

    fn read(&self, path: &str) -> Result<PlcValue, MachineError> {
        let (addr, ty, elem) = self.locate(path)?;
        let n = self.build.layout.scalar_size(ty) as usize;
        let bytes = self
            .vm
            .data()
            .get(addr..addr + n)
            .ok_or_else(|| MachineError(format!("vmasm: `{path}` is outside data memory")))?;
        let bits = bytes.iter().rev().fold(0u64, |a, &b| a << 8 | b as u64);
        if ty == Type::I1 {
            return Ok(PlcValue::from_bool(bits != 0));
        }
        Ok(PlcValue::from_bits(elem, bits))
    }

    fn write(&mut self, path: &str, value: PlcValue) -> Result<(), MachineError> {
        let (addr, ty, elem) = self.locate(path)?;
        if value.ty != elem {
            return Err(MachineError(format!(
                "`{path}` is {elem}, cannot write a {} value",
                value.ty
            )));
        }
        let n = self.build.layout.scalar_size(ty) as usize;
        let bits = if ty == Type::I1 {
            (value.bits != 0) as u64
        } else {
            value.bits
        };
        let data = self.vm.data_mut();
        let slot = data
            .get_mut(addr..addr + n)
            .ok_or_else(|| MachineError(format!("vmasm: `{path}` is outside data memory")))?;
        slot.copy_from_slice(&bits.to_le_bytes()[..n]);
        Ok(())
    }

    /// The fault word the program raises (`PLCC_FAULT`, not a status bit: the CPDev
    /// runtimes stop the VM on ARRAYBOUND).
    fn fault(&self) -> bool {
        let a = self.build.fault_addr as usize;
        self.vm.data().get(a..a + 2).is_some_and(|w| w != [0, 0])
    }

    fn clear_fault(&mut self) {
        let a = self.build.fault_addr as usize;
        if let Some(w) = self.vm.data_mut().get_mut(a..a + 2) {
            w.fill(0);
        }
    }

    fn set_watchdog(&mut self, limit: Option<Duration>) {
        self.watchdog = limit;
    }
}
