#include <icrkit/core/error.hpp>

namespace icrkit {
namespace {
std::string composeMessage(const std::string& source, const std::string& location, const std::string& detail) {
  std::string message = source;
  if (!location.empty()) message += ":" + location;
  if (!message.empty()) message += ": ";
  return message + detail;
}
}  // namespace

InputError::InputError(std::string source, std::string location, std::string detail)
    : std::runtime_error(composeMessage(source, location, detail)),
      source_(std::move(source)),
      location_(std::move(location)),
      detail_(std::move(detail)) {}

}  // namespace icrkit
