// libFuzzer target `seqinfo`: seqinfo.ini text -> SeqInfo (ParseSeqInfo). A
// file that parses must survive WriteSeqInfo and ReadSeqInfo unchanged.

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>

#include "fuzz_support.h"
#include "hcpf/metrics/mot_io.h"

namespace {

namespace metrics = hcpf::metrics;

bool Same(const metrics::SeqInfo& a, const metrics::SeqInfo& b) {
  return a.name == b.name && a.seq_length == b.seq_length &&
         std::memcmp(&a.frame_rate, &b.frame_rate, sizeof(double)) == 0 &&
         a.im_width == b.im_width && a.im_height == b.im_height && a.im_dir == b.im_dir &&
         a.im_ext == b.im_ext;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const hcpf::fuzz::ScratchDir scratch;
  const std::string text(reinterpret_cast<const char*>(data), size);
  hcpf::fuzz::ExpectInputErrorOnly([&] {
    const metrics::SeqInfo info = metrics::ParseSeqInfo(text, "seqinfo.ini");
    const std::string path = (scratch.path() / "seqinfo.ini").string();
    metrics::WriteSeqInfo(path, info);
    metrics::SeqInfo again;
    try {
      again = metrics::ReadSeqInfo(path);
    } catch (const hcpf::InputError& e) {
      hcpf::fuzz::Fail(std::string("a written seqinfo.ini is rejected: ") + e.what());
    }
    if (!Same(again, info)) hcpf::fuzz::Fail("seqinfo.ini does not round-trip");
  });
  return 0;
}
