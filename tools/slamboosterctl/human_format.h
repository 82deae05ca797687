#pragma once
// Human-readable lines for the protocol's messages (slamboosterctl without --json). Unknown fields are
// ignored; a message of an unknown class is shown as its JSON.

#include <nlohmann/json.hpp>
#include <string>

namespace sb::ctl {

std::string formatMessage(const nlohmann::json& message);
// STATUS as an aligned multi-line table.
std::string formatStatus(const nlohmann::json& status);

}  // namespace sb::ctl
