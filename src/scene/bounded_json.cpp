#include "scene/bounded_json.h"

#include <exception>

#include "core/strings.h"

namespace daisy {
namespace {

struct TooDeep {};

// nlohmann's what() is "[json.exception.parse_error.101] parse error at line L, column C: ...".
std::string withoutPrefix(std::string message) {
    if (message.starts_with("[json.exception")) {
        if (const auto bracket = message.find("] "); bracket != std::string::npos) {
            message.erase(0, bracket + 2);
        }
    }
    return message;
}

}  // namespace

Expected<nlohmann::json> parseBoundedJson(std::string_view text, int maxDepth) {
    if (text.size() > kMaxJsonBytes) {
        return Error{concat("the JSON text is ", formatBytes(double(text.size())), ", over the ",
                            formatBytes(double(kMaxJsonBytes)), " limit")};
    }
    // The callback sees each value's depth as the parser opens it; throwing stops the parse
    // before the tree grows any deeper.
    const nlohmann::json::parser_callback_t limitDepth =
        [maxDepth](int depth, nlohmann::json::parse_event_t event, nlohmann::json&) {
            if ((event == nlohmann::json::parse_event_t::object_start ||
                 event == nlohmann::json::parse_event_t::array_start) &&
                depth >= maxDepth) {
                throw TooDeep{};
            }
            return true;
        };
    try {
        return nlohmann::json::parse(text.begin(), text.end(), limitDepth);
    } catch (const TooDeep&) {
        return Error{concat("JSON nests deeper than ", maxDepth,
                            " levels (arrays or objects inside each other); refused before "
                            "parsing further")};
    } catch (const nlohmann::json::parse_error& e) {
        return Error{concat("invalid JSON: ", withoutPrefix(e.what()))};
    } catch (const nlohmann::json::exception& e) {
        return Error{concat("invalid JSON: ", withoutPrefix(e.what()))};
    } catch (const std::bad_alloc&) {
        return Error{
            concat("out of memory parsing ", formatBytes(double(text.size())), " of JSON")};
    }
}

const nlohmann::json* jsonMember(const nlohmann::json& object, const char* key) {
    if (!object.is_object()) return nullptr;
    const auto it = object.find(key);
    return it == object.end() ? nullptr : &*it;
}

std::string describeJson(const nlohmann::json& value) {
    if (value.is_null()) return "null";
    std::string text;
    if (value.is_object()) {
        text = value.empty() ? "{}" : "{...}";
    } else if (value.is_array()) {
        text = value.empty() ? "[]" : concat("[...] of ", value.size());
    } else {
        text = value.dump();
        if (text.size() > 40) text = text.substr(0, 37) + "...";
    }
    return concat(value.type_name(), ' ', text);
}

}  // namespace daisy
