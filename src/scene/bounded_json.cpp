#include "scene/bounded_json.h"

#include <exception>
#include <set>
#include <vector>

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

// A SAX pass that finds the first key named twice in one object, and its JSON path. Linear in
// the text: one set of keys per open object.
class DuplicateKeyFinder {
public:
    using number_integer_t = nlohmann::json::number_integer_t;
    using number_unsigned_t = nlohmann::json::number_unsigned_t;
    using number_float_t = nlohmann::json::number_float_t;
    using string_t = nlohmann::json::string_t;
    using binary_t = nlohmann::json::binary_t;

    std::string duplicate;  // "floor: the key \"values\" appears twice ..." once found

    bool null() { return value(); }
    bool boolean(bool) { return value(); }
    bool number_integer(number_integer_t) { return value(); }
    bool number_unsigned(number_unsigned_t) { return value(); }
    bool number_float(number_float_t, const string_t&) { return value(); }
    bool string(string_t&) { return value(); }
    bool binary(binary_t&) { return value(); }
    bool start_object(std::size_t) {
        scopes_.push_back({true, {}, {}, 0});
        return true;
    }
    bool key(string_t& name) {
        Scope& scope = scopes_.back();
        if (!scope.keys.insert(name).second) {
            const std::string where = path();
            duplicate = where.empty()
                ? concat("the key \"", name, "\" appears twice at the top level")
                : concat(where, ": the key \"", name, "\" appears twice in this object");
            return false;
        }
        scope.current = name;
        return true;
    }
    bool end_object() { return close(); }
    bool start_array(std::size_t) {
        scopes_.push_back({false, {}, {}, 0});
        return true;
    }
    bool end_array() { return close(); }
    bool parse_error(std::size_t, const std::string&, const nlohmann::json::exception&) {
        return false;  // the DOM parse that follows reports syntax errors
    }

private:
    struct Scope {
        bool object;
        std::set<std::string> keys;
        std::string current;  // the object's key being read
        std::size_t index;  // the array's element being read
    };
    std::vector<Scope> scopes_;

    bool value() {
        if (!scopes_.empty() && !scopes_.back().object) ++scopes_.back().index;
        return true;
    }
    bool close() {
        scopes_.pop_back();
        return value();
    }
    // "floor.reflectance", "materials[2].name": where the parser is now.
    std::string path() const {
        std::string out;
        for (std::size_t k = 0; k + 1 < scopes_.size(); ++k) {
            const Scope& scope = scopes_[k];
            out += scope.object ? (out.empty() ? "" : ".") + scope.current
                                : concat("[", scope.index, "]");
        }
        return out;
    }
};

}  // namespace

Expected<nlohmann::json> parseBoundedJson(std::string_view text, int maxDepth, JsonKeys keys) {
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
        if (keys == JsonKeys::Unique) {
            DuplicateKeyFinder finder;
            nlohmann::json::sax_parse(text.begin(), text.end(), &finder);
            if (!finder.duplicate.empty()) return Error{finder.duplicate};
        }
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
