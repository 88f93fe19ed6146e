#include "io/json_fields.h"

#include <fmt/format.h>

#include <cmath>

namespace hexmesh {

namespace {

// Appends the JSON text of `value` to `text` until it is longer than `limit`: nested arrays
// and objects only as deep as that needs (a value nested 100 000 deep costs a few frames).
void append_brief(const nlohmann::json& value, std::string& text, size_t limit) {
    if (text.size() > limit) return;
    if (value.is_array() || value.is_object()) {
        text += value.is_array() ? '[' : '{';
        bool first = true;
        for (auto it = value.begin(); it != value.end() && text.size() <= limit; ++it) {
            if (!first) text += ',';
            first = false;
            if (value.is_object()) text += nlohmann::json(it.key()).dump() + ':';
            append_brief(*it, text, limit);
        }
        text += value.is_array() ? ']' : '}';
    } else {
        text += value.dump();
    }
}

}  // namespace

std::string describe(const nlohmann::json& value) {
    std::string text;
    append_brief(value, text, 40);
    if (text.size() > 40) text = text.substr(0, 37) + "...";
    return fmt::format("{} {}", value.type_name(), text);
}

JsonFields::JsonFields(const nlohmann::json& object, std::string file, std::string path)
    : object_(object), file_(std::move(file)), path_(std::move(path)) {
    if (!object_.is_object()) {
        throw InputError(fmt::format("{}: {}: expected an object, got {}", file_,
                                     path_.empty() ? "top level" : path_, describe(object_)));
    }
}

std::string JsonFields::path_of(const std::string& key) const {
    return path_.empty() ? key : path_ + "." + key;
}

void JsonFields::fail(const std::string& key, const std::string& expected) const {
    const std::string got = object_.contains(key) ? describe(object_.at(key)) : "nothing";
    throw InputError(
        fmt::format("{}: {}: expected {}, got {}", file_, path_of(key), expected, got));
}

void JsonFields::allow_only(std::initializer_list<const char*> allowed) const {
    for (const auto& item : object_.items()) {
        bool known = false;
        for (const char* a : allowed) known = known || item.key() == a;
        if (!known) {
            std::string list;
            for (const char* a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
            throw InputError(fmt::format("{}: {}: unknown key (allowed here: {})", file_,
                                         path_of(item.key()), list));
        }
    }
}

double JsonFields::number(const char* key, double fallback) const {
    if (!has(key)) return fallback;
    const auto& v = object_.at(key);
    if (!v.is_number() || !std::isfinite(v.get<double>())) fail(key, "a finite number");
    return v.get<double>();
}

double JsonFields::positive_number(const char* key, double fallback) const {
    const double x = number(key, fallback);
    if (has(key) && !(x > 0)) fail(key, "a positive number");
    return x;
}

double JsonFields::required_positive_number(const char* key) const {
    if (!has(key)) fail(key, "a positive number");
    return positive_number(key, 0);
}

int JsonFields::integer(const char* key, int fallback, int min, int max) const {
    if (!has(key)) return fallback;
    const auto& v = object_.at(key);
    const std::string expected = fmt::format("an integer in [{}, {}]", min, max);
    if (!v.is_number_integer()) fail(key, expected);
    const auto x = v.get<long long>();
    if (x < min || x > max) fail(key, expected);
    return int(x);
}

Vec3 JsonFields::vec3(const char* key, const Vec3& fallback) const {
    if (!has(key)) return fallback;
    const auto& v = object_.at(key);
    if (!v.is_array() || v.size() != 3) fail(key, "an array of 3 numbers");
    Vec3 p;
    for (int d = 0; d < 3; ++d) {
        if (!v[d].is_number() || !std::isfinite(v[d].get<double>()))
            fail(key, "an array of 3 finite numbers");
        p[d] = v[d].get<double>();
    }
    return p;
}

Vec3 JsonFields::positive_vec3(const char* key, const Vec3& fallback) const {
    const Vec3 p = vec3(key, fallback);
    if (has(key) && !(p.minCoeff() > 0)) fail(key, "an array of 3 positive numbers");
    return p;
}

std::string JsonFields::choice(const char* key, const std::string& fallback,
                               const std::vector<const char*>& allowed) const {
    std::string list;
    for (const char* a : allowed) list += (list.empty() ? "" : " | ") + std::string(a);
    if (!has(key)) return fallback;
    const auto& v = object_.at(key);
    if (!v.is_string()) fail(key, "one of " + list);
    for (const char* a : allowed)
        if (v.get<std::string>() == a) return a;
    fail(key, "one of " + list);
}

JsonFields JsonFields::object(const char* key) const {
    if (!has(key) || !object_.at(key).is_object()) fail(key, "an object");
    return JsonFields(object_.at(key), file_, path_of(key));
}

}  // namespace hexmesh
