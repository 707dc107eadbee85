#include "odoloc/cli/spidev_link.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <linux/spi/spidev.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <utility>

#include "odoloc/cli/errors.hpp"

namespace odoloc::cli {
namespace {

constexpr std::uint8_t kBitsPerWord = 8;

}  // namespace

SpidevLink::SpidevLink(std::string device, std::uint32_t speed_hz)
    : device_(std::move(device)), speed_hz_(speed_hz) {
  fd_ = ::open(device_.c_str(), O_RDWR | O_CLOEXEC);
  if (fd_ < 0)
    throw UsageError(fmt::format("cannot open {}: {}", device_, std::strerror(errno)));
  try {
    const std::uint8_t mode = SPI_MODE_0;
    configure(SPI_IOC_WR_MODE, &mode, "SPI_IOC_WR_MODE");
    configure(SPI_IOC_WR_BITS_PER_WORD, &kBitsPerWord, "SPI_IOC_WR_BITS_PER_WORD");
    configure(SPI_IOC_WR_MAX_SPEED_HZ, &speed_hz_, "SPI_IOC_WR_MAX_SPEED_HZ");
  } catch (...) {
    ::close(fd_);
    throw;
  }
}

SpidevLink::~SpidevLink() {
  ::close(fd_);
}

void SpidevLink::configure(unsigned long request, const void* value, const char* what) {
  if (::ioctl(fd_, request, value) < 0)
    throw UsageError(
        fmt::format("cannot configure {} ({}): {}", device_, what, std::strerror(errno)));
}

void SpidevLink::transfer(std::span<const std::uint8_t> mosi, std::span<std::uint8_t> miso) {
  if (miso.size() != mosi.size())
    throw sw::BusError(fmt::format("SPI transfer on {}: {} bytes out, {} bytes in", device_,
                                   mosi.size(), miso.size()));
  spi_ioc_transfer xfer{};
  xfer.tx_buf = reinterpret_cast<std::uintptr_t>(mosi.data());
  xfer.rx_buf = reinterpret_cast<std::uintptr_t>(miso.data());
  xfer.len = static_cast<std::uint32_t>(mosi.size());
  xfer.speed_hz = speed_hz_;
  xfer.bits_per_word = kBitsPerWord;
  xfer.cs_change = 0;  // chip select stays asserted for the whole frame, released after it
  if (::ioctl(fd_, SPI_IOC_MESSAGE(1), &xfer) < 0)
    throw sw::BusError(fmt::format("SPI transfer on {} failed: {}", device_, std::strerror(errno)));
}

void SpidevLink::set_mode3(bool mode3) {
  const std::uint8_t mode = mode3 ? SPI_MODE_3 : SPI_MODE_0;
  if (::ioctl(fd_, SPI_IOC_WR_MODE, &mode) < 0)
    throw sw::BusError(fmt::format("cannot switch {} to SPI mode {}: {}", device_, mode3 ? 3 : 0,
                                   std::strerror(errno)));
}

}  // namespace odoloc::cli
