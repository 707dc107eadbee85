// The register interface, written once: the SPI slave (logic/spi_slave.hpp)
// and the register file (logic/register_file.hpp) on one fabric clock, pins
// and the fabric's status in, MISO, the configuration words and the
// one-clock pulses out (docs/spi.md). The cycle model's composite
// (rtl/register_interface.hpp, which rtl::OdolocChip composes) wires its
// children with the functions below; the HLS kernel (hls/regfile_kernel.hpp)
// runs next().
//
// The wires that cross the two children, from the current registers only:
//   slave -> register file   Port: the strobes, addresses and write words
//   register file -> slave   read_data (read() of the requested word, the
//                            clock after read_strobe), write_refused (the
//                            commit clock), crc_enable and spi_mode3 (top.ctrl)
// C++14, no heap, no containers, static loop bounds (int_family.hpp).
#pragma once

#include "odoloc/logic/int_family.hpp"
#include "odoloc/logic/register_file.hpp"
#include "odoloc/logic/spi_slave.hpp"

namespace odoloc {
namespace logic {
namespace register_interface {

template <class F>
struct Regs {
  spi::SlaveRegs<F> slave;
  regfile::Regs<F> registers;
};

template <class F>
struct Pins {
  uint<F, 1> sclk{0}, cs_n{1}, mosi{0};  // asynchronous
  uint<F, 1> reset{0};                   // synchronous
};

template <class F>
struct RegisterInterface {
  using RegisterFile = regfile::RegisterFile<F>;

  // The word the slave latches: read() of the word it requested.
  template <class Status>
  static spi::Word<F> read_data(const regfile::Regs<F>& registers, const regfile::Port<F>& port,
                                const Status& status) {
    if (is_zero(port.read_strobe))
      return spi::Word<F>(0);
    return RegisterFile::read(registers, port.read_address, status);
  }
  // read_data and write_refused: 0 in a clock without a strobe.
  static spi::SlaveIn<F> slave_in(const regfile::Regs<F>& registers, const Pins<F>& pins,
                                  const spi::Word<F>& read_data, const uint<F, 1>& write_refused) {
    spi::SlaveIn<F> s;
    s.sclk = pins.sclk;
    s.cs_n = pins.cs_n;
    s.mosi = pins.mosi;
    s.crc_enable = RegisterFile::crc_enable(registers);
    s.spi_mode3 = RegisterFile::spi_mode3(registers);
    s.read_data = read_data;
    s.write_refused = write_refused;
    s.reset = pins.reset;
    return s;
  }
  template <class Status>
  static regfile::In<F, Status> registers_in(const regfile::Port<F>& port, const Pins<F>& pins,
                                             const spi::Word<F>& read_data, const Status& status) {
    regfile::In<F, Status> r;
    r.spi = port;
    r.read_data = read_data;
    r.status = status;
    r.reset = pins.reset;
    return r;
  }

  // One fabric clock of the whole interface.
  template <class Status>
  static Regs<F> next(const Regs<F>& r, const Pins<F>& pins, const Status& status) {
    const regfile::Port<F> port = regfile::port(r.slave.engine, r.slave.buffer);
    const spi::Word<F> data = read_data(r.registers, port, status);
    Regs<F> n;
    n.slave = spi::Slave<F>::next(
        r.slave, slave_in(r.registers, pins, data, RegisterFile::write_refused(port)));
    n.registers = RegisterFile::next(r.registers, registers_in(port, pins, data, status));
    return n;
  }
};

}  // namespace register_interface
}  // namespace logic
}  // namespace odoloc
