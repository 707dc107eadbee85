// Top function of the EPPM kernel (eppm_kernel.hpp): a free-running block,
// one call = one 50 MHz fabric clock, so the pipeline takes one call per
// clock (II=1) and the block needs no start/done handshake (ap_ctrl_none).
// Ports are disaggregated into one wire per field, as the RTL block has them;
// the filter's per-line counters are partitioned into single registers, since
// both are read and written in every clock.
#include "odoloc/hls/eppm_kernel.hpp"

ODOLOC_HLS_TOP void odoloc_eppm(const odoloc::hls::eppm::Inputs& in,
                                odoloc::hls::eppm::Outputs& out) {
#pragma hls_design top
#pragma HLS interface mode = ap_ctrl_none port = return
#pragma HLS interface mode = ap_none port = in
#pragma HLS interface mode = ap_none port = out
#pragma HLS disaggregate variable = in
#pragma HLS disaggregate variable = out
#pragma HLS pipeline II = 1
  static odoloc::hls::eppm::Registers regs;
#pragma HLS array_partition variable = regs.conditioner.line complete
  odoloc::hls::eppm::step(regs, in, out);
}
