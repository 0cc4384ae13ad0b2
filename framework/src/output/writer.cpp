// Output helpers shared by writers and function objects.
#include "scree/output/writer.hpp"

#include <atomic>
#include <system_error>
#include <unistd.h>

#include "scree/output/function_object.hpp"

namespace scree {

Writer::~Writer() = default;
FunctionObject::~FunctionObject() = default;

void write_file_atomically(const std::filesystem::path& target,
                           const std::function<void(const std::filesystem::path&)>& fill) {
  static std::atomic<int> counter{0};
  std::filesystem::create_directories(target.parent_path());
  // A hidden temporary in the same directory (so the rename is atomic on one filesystem).
  const auto tmp = target.parent_path() / ("." + target.filename().string() + ".tmp" + std::to_string(::getpid()) +
                                           "_" + std::to_string(counter++));
  try {
    fill(tmp);
    std::filesystem::rename(tmp, target);
  } catch (...) {
    std::error_code ec;
    std::filesystem::remove(tmp, ec);
    throw;
  }
}

}  // namespace scree
