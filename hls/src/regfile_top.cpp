// Top function of the register interface kernel (regfile_kernel.hpp): the
// SPI slave and the register file, a free-running block, one call = one
// 50 MHz fabric clock, so the pipeline takes one call per clock (II=1) and
// the block needs no start/done handshake (ap_ctrl_none). Ports are
// disaggregated into one wire per field, the arrays partitioned into one
// wire per word; the stored configuration words, the snapshot bank and the
// write buffer are registers, not RAMs: every stored word drives a
// configuration port all the time, and a burst's words commit in one clock.
#include "odoloc/hls/regfile_kernel.hpp"

ODOLOC_HLS_TOP void odoloc_regfile(const odoloc::hls::regfile::Inputs& in,
                                   odoloc::hls::regfile::Outputs& out) {
#pragma hls_design top
#pragma HLS interface mode = ap_ctrl_none port = return
#pragma HLS interface mode = ap_none port = in
#pragma HLS interface mode = ap_none port = out
#pragma HLS disaggregate variable = in
#pragma HLS disaggregate variable = out
#pragma HLS array_partition variable = in.status.bank complete
#pragma HLS array_partition variable = out.config complete
#pragma HLS array_partition variable = out.pulse complete
#pragma HLS array_partition variable = out.pops complete
#pragma HLS pipeline II = 1
  static odoloc::hls::regfile::Registers regs;
#pragma HLS array_partition variable = regs.slave.buffer.words complete
#pragma HLS array_partition variable = regs.registers.stored.word complete
#pragma HLS array_partition variable = regs.registers.snapshot complete
#pragma HLS array_partition variable = regs.registers.pulse complete
  odoloc::hls::regfile::step(regs, in, out);
}
