// Top function of the sequential CORDIC kernel (cordic_kernel.hpp): a
// free-running block, one call = one 50 MHz fabric clock, so the pipeline
// takes one call per clock (II=1) and the block needs no start/done handshake
// (ap_ctrl_none). Ports are disaggregated into one wire per field, as the
// RTL block has them.
#include "odoloc/hls/cordic_kernel.hpp"

ODOLOC_HLS_TOP void odoloc_cordic(const odoloc::hls::cordic::Inputs& in,
                                  odoloc::hls::cordic::Outputs& out) {
#pragma hls_design top
#pragma HLS interface mode = ap_ctrl_none port = return
#pragma HLS interface mode = ap_none port = in
#pragma HLS interface mode = ap_none port = out
#pragma HLS disaggregate variable = in
#pragma HLS disaggregate variable = out
#pragma HLS pipeline II = 1
  static odoloc::hls::cordic::Registers regs;
  odoloc::hls::cordic::step(regs, in, out);
}
