// Top function of the SPI register file kernel (regfile_kernel.hpp): one call
// = one SPI transaction, handed over when the frame ends (cs_n rises), so the
// block has a start/done handshake (ap_ctrl_hs) and is not pipelined at the
// top: a frame lasts at least 16 SCLK edges (> 100 fabric clocks at the
// 6.25 MHz limit), far longer than the call's two passes over the burst
// words (each pipelined with II=1). Ports are disaggregated into one wire per
// field, the arrays partitioned into one wire per word; the stored
// configuration words are registers, not a RAM: every one drives a
// configuration port all the time.
#include "odoloc/hls/regfile_kernel.hpp"

ODOLOC_HLS_TOP void odoloc_regfile(const odoloc::hls::regfile::Inputs& in,
                                   odoloc::hls::regfile::Outputs& out) {
#pragma hls_design top
#pragma HLS interface mode = ap_ctrl_hs port = return
#pragma HLS interface mode = ap_none port = in
#pragma HLS interface mode = ap_none port = out
#pragma HLS disaggregate variable = in
#pragma HLS disaggregate variable = out
#pragma HLS array_partition variable = in.data complete
#pragma HLS array_partition variable = in.status complete
#pragma HLS array_partition variable = out.miso_data complete
#pragma HLS array_partition variable = out.config complete
#pragma HLS array_partition variable = out.pulse complete
#pragma HLS array_partition variable = out.pops complete
  static odoloc::hls::regfile::Registers regs;
#pragma HLS array_partition variable = regs.stored.word complete
  odoloc::hls::regfile::step(regs, in, out);
}
