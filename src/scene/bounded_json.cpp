#include "scene/bounded_json.h"

#include <exception>

#include "core/strings.h"

namespace daisy {
namespace {

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
    // Depth by one linear scan of the brackets outside strings, before parsing: nlohmann's parser
    // is iterative, but the tree it builds is destroyed recursively, and a parser callback would
    // re-scan each parent after every closed value (quadratic in the members of an object).
    int depth = 0;
    bool inString = false, escaped = false;
    for (const char c : text) {
        if (inString) {
            if (escaped) {
                escaped = false;
            } else if (c == '\\') {
                escaped = true;
            } else if (c == '"') {
                inString = false;
            }
        } else if (c == '"') {
            inString = true;
        } else if (c == '[' || c == '{') {
            if (++depth > maxDepth) {
                return Error{concat("JSON nests deeper than ", maxDepth,
                                    " levels (arrays or objects inside each other); refused "
                                    "before parsing further")};
            }
        } else if (c == ']' || c == '}') {
            --depth;
        }
    }
    try {
        return nlohmann::json::parse(text.begin(), text.end());
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
