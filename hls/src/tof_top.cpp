// Top function of the TOF capture kernel (tof_kernel.hpp): a free-running
// block, one call = one 50 MHz fabric clock, so the pipeline takes one call
// per clock (II=1) and the block needs no start/done handshake
// (ap_ctrl_none). Ports are disaggregated into one wire per field, as the RTL
// block has them; the port arrays (per channel, per window entry) and the
// register arrays (per line, per channel, per FIFO slot) are partitioned into
// single registers, since every element is read or written in every clock.
#include "odoloc/hls/tof_kernel.hpp"

ODOLOC_HLS_TOP void odoloc_tof(const odoloc::hls::tof::Inputs& in, odoloc::hls::tof::Outputs& out) {
#pragma hls_design top
#pragma HLS interface mode = ap_ctrl_none port = return
#pragma HLS interface mode = ap_none port = in
#pragma HLS interface mode = ap_none port = out
#pragma HLS disaggregate variable = in
#pragma HLS disaggregate variable = out
#pragma HLS array_partition variable = in.rx_pulses complete
#pragma HLS array_partition variable = in.rx_config complete
#pragma HLS array_partition variable = out.sync_entry complete
#pragma HLS array_partition variable = out.rx complete dim = 0
#pragma HLS pipeline II = 1
  static odoloc::hls::tof::Registers regs;
#pragma HLS array_partition variable = regs.conditioner.line complete
#pragma HLS array_partition variable = regs.sync_fifo.slots complete
#pragma HLS array_partition variable = regs.rx complete dim = 0
  odoloc::hls::tof::step(regs, in, out);
}
