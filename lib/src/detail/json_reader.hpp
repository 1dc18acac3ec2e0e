#pragma once
// Strict reading of one JSON object of a scene: typed getters with defaults and ranges, and a
// final check that rejects every key nobody asked for. Messages name the full key path.

#include "detail/check.hpp"
#include "gapchain/scene.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

namespace gapchain::detail {

/// A JSON value as a message shows it: as the user wrote it (JSON writes NaN and infinities as
/// null), bytes that are not UTF-8 replaced, cut after 60 characters (a 3-million-entry array
/// was printed whole).
template <class Json>
std::string shown_json(const Json& v) {
    if (v.is_number_float() && !std::isfinite(v.template get<double>()))
        return std::isnan(v.template get<double>())
                   ? "nan"
                   : (v.template get<double>() > 0 ? "inf" : "-inf");
    std::string text = v.dump(-1, ' ', false, Json::error_handler_t::replace);
    if (text.size() > 60) text = text.substr(0, 57) + "...";
    return text;
}

/// A key or text as a message shows it: as written, or JSON-escaped where it holds a control
/// character (a NUL in a key cut the message there: "gapchain-sim: model").
inline std::string visible(const std::string& text) {
    if (std::none_of(text.begin(), text.end(),
                     [](char c) { return static_cast<unsigned char>(c) < 0x20; }))
        return text;
    const std::string quoted =
        nlohmann::json(text).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
    return quoted.substr(1, quoted.size() - 2);
}

class SectionReader {
public:
    SectionReader(const nlohmann::json& object, std::string path,
                  std::vector<std::string> allowed = {})
        : m_object(object), m_path(std::move(path)), m_allowed(std::move(allowed)) {
        if (!m_object.is_object())
            throw SceneError((m_path.empty() ? "scene" : m_path) + ": must be a JSON object");
    }

    // The child object under key (an empty object when the key is absent).
    [[nodiscard]] SectionReader section(const std::string& key) const {
        static const nlohmann::json empty = nlohmann::json::object();
        return SectionReader(m_object.contains(key) ? m_object.at(key) : empty, full(key));
    }
    void allow(std::initializer_list<std::string> keys) {
        m_allowed.insert(m_allowed.end(), keys.begin(), keys.end());
    }
    void allow(const std::vector<std::string>& keys) {
        m_allowed.insert(m_allowed.end(), keys.begin(), keys.end());
    }
    [[nodiscard]] bool has(const std::string& key) const { return m_object.contains(key); }
    // Whether key is present and holds a string.
    [[nodiscard]] bool has_text(const std::string& key) const {
        return has(key) && m_object.at(key).is_string();
    }

    /// Python's scenes carry a non-finite number as its text ("inf", "nan"): say what it is.
    template <class Value>
    static bool is_non_finite_text(const Value& v) {
        static const std::set<std::string> non_finite{"nan",  "inf",      "-inf",     "+inf",
                                                      "-nan", "infinity", "-infinity"};
        return v.is_string() && non_finite.count(v.template get<std::string>()) != 0;
    }

    double number(const std::string& key, double fallback, double lo, double hi,
                  Bound bound = Bound::closed) const {
        if (!has(key)) return fallback;
        const auto& v = m_object.at(key);
        if (is_non_finite_text(v))
            throw SceneError(full(key) + ": must be a finite number" + range(lo, hi, bound) +
                             ", got " + v.template get<std::string>());
        if (!v.is_number())
            throw SceneError(full(key) + ": must be a number" + range(lo, hi, bound) + ", got " +
                             shown_json(v));
        const double x = v.get<double>();
        try {
            require_range(full(key), x, lo, hi, bound);
        } catch (const std::invalid_argument& e) {
            throw SceneError(e.what());
        }
        return x;
    }

    long integer(const std::string& key, long fallback, long lo, long hi) const {
        if (!has(key)) return fallback;
        const auto& v = m_object.at(key);
        double x = 0.0;
        if (v.is_number_integer()) {
            x = static_cast<double>(v.get<long long>());
        } else if (v.is_number_float() && std::isfinite(v.get<double>()) &&
                   v.get<double>() == std::floor(v.get<double>())) {
            x = v.get<double>();
        } else {
            throw SceneError(
                full(key) + ": must be an integer in [" + std::to_string(lo) + ", " +
                std::to_string(hi) + "], got " +
                (is_non_finite_text(v) ? v.template get<std::string>() : shown_json(v)));
        }
        if (x < static_cast<double>(lo) || x > static_cast<double>(hi))
            throw SceneError(full(key) + ": must be an integer in [" + std::to_string(lo) + ", " +
                             std::to_string(hi) + "], got " + shown_json(v));
        return static_cast<long>(x);
    }

    bool boolean(const std::string& key, bool fallback) const {
        if (!has(key)) return fallback;
        const auto& v = m_object.at(key);
        if (!v.is_boolean())
            throw SceneError(full(key) + ": must be true or false, got " + shown_json(v));
        return v.get<bool>();
    }

    std::string text(const std::string& key, const std::string& fallback,
                     const std::vector<std::string>& choices) const {
        if (!has(key)) return fallback;
        const auto& v = m_object.at(key);
        const std::string s = v.is_string() ? v.get<std::string>() : std::string();
        if (!v.is_string())
            throw SceneError(full(key) + ": must be a string" +
                             (choices.empty() ? "" : ", one of " + join(choices)) + ", got " +
                             shown_json(v));
        // A control character cut the caller's message at it ("rk4\u0000x" named as "rk4").
        if (visible(s) != s)
            throw SceneError(full(key) + ": must hold no control characters, got " + shown_json(v));
        // Empty choices: the caller validates the value itself.
        if (!choices.empty() && std::find(choices.begin(), choices.end(), s) == choices.end())
            throw SceneError(full(key) + ": must be one of " + join(choices) + ", got " +
                             shown_json(v));
        return s;
    }

    // Rejects any key that was not allowed.
    void finish() const {
        for (const auto& [key, value] : m_object.items()) {
            (void)value;
            if (std::find(m_allowed.begin(), m_allowed.end(), key) == m_allowed.end())
                throw SceneError(full(key) +
                                 ": unknown key; accepted keys here: " + join(m_allowed));
        }
    }

    // The dotted name of key in this section ("run.periods").
    [[nodiscard]] std::string full(const std::string& key) const {
        return m_path.empty() ? visible(key) : m_path + "." + visible(key);
    }

private:
    static std::string join(const std::vector<std::string>& items) {
        std::string s;
        for (const auto& i : items)
            s += (s.empty() ? "" : ", ") + i;
        return s;
    }
    static std::string range(double lo, double hi, Bound bound) {
        return std::string(" in ") + (bound == Bound::open_low ? "(" : "[") + format_number(lo) +
               ", " + format_number(hi) + "]";
    }

    const nlohmann::json& m_object;
    std::string m_path;
    std::vector<std::string> m_allowed;
};

} // namespace gapchain::detail

namespace gapchain::detail {

/// The first number of JSON text that gapchain cannot read as written (number_text_error():
/// 1e-999 reads as 0, a subnormal loses digits, 1e999 overflows): its ordinal among the text's
/// numbers (1 for the first) and the message. Strings are skipped.
struct UnreadableNumber {
    std::size_t ordinal = 0;
    std::string message;
};
std::optional<UnreadableNumber> first_unreadable_number(std::string_view text);

/// The NaN or Infinity literal (as other languages write them; JSON has neither) that a parse
/// error at byte offset `last_read` (1-based, nlohmann's parse_error::byte) stopped in, where it
/// stands as a value: after ':' in an object (in_object), after '[' or ',' in an array. Empty
/// otherwise.
std::string non_finite_literal_at(std::string_view text, std::size_t last_read, bool in_object);

/// An nlohmann exception's message without its "[json.exception.parse_error.101] " prefix,
/// which names nlohmann's internals, not the file's fault, and with every byte outside printable
/// ASCII written \xNN: the message quotes the bytes last read, which may be ill-formed UTF-8
/// (Python then raised a ValueError with no message at all) or control characters.
inline std::string plain_what(const std::exception& e) {
    std::string what = e.what();
    if (const auto end = what.find("] ");
        what.rfind("[json.exception.", 0) == 0 && end != std::string::npos)
        what.erase(0, end + 2);
    std::string printable;
    for (const unsigned char c : what) {
        if (c >= 0x20 && c < 0x7f) {
            printable.push_back(static_cast<char>(c));
            continue;
        }
        static constexpr char hex[] = "0123456789ABCDEF";
        printable += {'\\', 'x', hex[c >> 4], hex[c & 15]};
    }
    return printable;
}

/// The deepest nesting of arrays and objects a scene or study file may have.
constexpr int max_json_depth = 64;

/// Where a strict parse stands in the text's objects and arrays: the path of the key being
/// read ("model.fc"), the keys each open object has had, and messages named by them.
class JsonKeyTrail {
public:
    /// Messages start "source: " (none when source is empty) and name keys under `within` (a
    /// --set value's key: "model.scatter").
    JsonKeyTrail(std::string source, std::string within)
        : m_source(std::move(source)), m_within(std::move(within)) {}
    /// An object (or array) opens / closes.
    void open(bool object);
    void close(bool object);
    /// A key of the innermost object; throws SceneError if that object had it already.
    void key(const std::string& name);
    /// Whether the innermost open container is an object.
    [[nodiscard]] bool in_object() const { return !m_containers.empty() && m_containers.back(); }
    /// A fault at key (a path within the text), named with its source and full path.
    [[nodiscard]] SceneError error_at(const std::string& key, const std::string& rule) const;
    /// A value's fault, named by the key it belongs to (in an array, the array's key).
    [[nodiscard]] SceneError value_error(const std::string& rule) const;

private:
    struct Level {
        std::set<std::string> keys;
        std::string path;
        std::string last_key;
    };
    std::string m_source;
    std::string m_within;
    std::vector<Level> m_levels;    // the open objects
    std::vector<bool> m_containers; // the open objects and arrays, innermost last
};

/// Parses JSON text (nlohmann::json or ordered_json) and refuses a key given twice in one
/// object, at any depth, naming its path ("model.Nm: duplicate key"): nlohmann would keep the
/// last silently. Malformed text throws SceneError naming source; so do a number that
/// overflows or underflows, a NaN or Infinity literal and nesting beyond max_json_depth, named
/// by the key they belong to. source and within as JsonKeyTrail takes them.
template <class Json>
Json parse_json_strictly(std::string_view text, const std::string& source,
                         const std::string& within = {}) {
    // Rare, so found by a scan first; the callback then counts numbers up to it to name its key.
    const auto unreadable = first_unreadable_number(text);
    std::size_t numbers_read = 0;
    JsonKeyTrail trail(source, within);
    auto callback = [&](int depth, typename Json::parse_event_t event, Json& parsed) {
        using Event = typename Json::parse_event_t;
        // A scene is a few levels deep; a value nested 100,000 deep overflowed the stack where
        // a message printed it.
        if (depth >= max_json_depth)
            throw trail.value_error("nested more than " + std::to_string(max_json_depth) +
                                    " levels deep (arrays and objects, counted from the top of "
                                    "the text)");
        if (event == Event::object_start || event == Event::array_start)
            trail.open(event == Event::object_start);
        else if (event == Event::object_end || event == Event::array_end)
            trail.close(event == Event::object_end);
        else if (event == Event::key)
            trail.key(parsed.template get<std::string>());
        else if (event == Event::value && unreadable && parsed.is_number() &&
                 ++numbers_read == unreadable->ordinal)
            throw trail.value_error(unreadable->message);
        return true;
    };
    try {
        return Json::parse(text, callback);
    } catch (const typename Json::out_of_range& e) {
        // Number overflow (1e999): the lexer throws before the value reaches the callback, so
        // the key it belongs to is the last one read; the scan found the number first.
        if (unreadable) throw trail.value_error(unreadable->message);
        throw trail.error_at("", "malformed JSON: " + plain_what(e));
    } catch (const typename Json::parse_error& e) {
        const std::string literal = non_finite_literal_at(text, e.byte, trail.in_object());
        if (literal.empty()) throw trail.error_at("", "malformed JSON: " + plain_what(e));
        throw trail.value_error("must be a finite number (JSON has no NaN or Infinity), got " +
                                literal);
    } catch (const typename Json::exception& e) {
        throw trail.error_at("", "malformed JSON: " + plain_what(e));
    }
}

/// A path a scene names (excitation.file), resolved as the scene reader resolves it: relative
/// to the folder of the scene's source (a file path; "<string>" and other sources in angle
/// brackets leave it as written).
std::string scene_relative_path(const std::string& path, const std::string& source);

/// Reads a whole text file; `what` names it in messages ("scene", "study"). A directory, or a
/// file that cannot be read, is a SceneError naming the path and the reason.
std::string read_text_file(const std::string& path, const std::string& what);

} // namespace gapchain::detail
