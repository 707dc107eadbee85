// Top function of the odometry datapath kernel (odometry_kernel.hpp): a
// free-running block, one call = one 50 MHz fabric clock, so the pipeline
// takes one call per clock (II=1) and the block needs no start/done handshake
// (ap_ctrl_none). Ports are disaggregated into one wire per field, as the
// RTL block has them. The registers are scalars in nested structs: no arrays,
// so nothing to partition.
#include "odoloc/hls/odometry_kernel.hpp"

ODOLOC_HLS_TOP void odoloc_odometry(const odoloc::hls::odometry::Inputs& in,
                                    odoloc::hls::odometry::Outputs& out) {
#pragma hls_design top
#pragma HLS interface mode = ap_ctrl_none port = return
#pragma HLS interface mode = ap_none port = in
#pragma HLS interface mode = ap_none port = out
#pragma HLS disaggregate variable = in
#pragma HLS disaggregate variable = out
#pragma HLS pipeline II = 1
  static odoloc::hls::odometry::Registers regs;
  odoloc::hls::odometry::step(regs, in, out);
}
