// Typed, validated access to the fields of a JSON object, with key paths in every message.
#pragma once

#include <array>
#include <cstddef>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "hexmesh/core/types.h"
#include "io/input_error.h"

namespace hexmesh {

// A JSON object at a key path ("grid", "geometry.union[1]") of a file. Accessors throw
// InputError "FILE: PATH.KEY: expected ..., got ..." on a wrong type or range.
class JsonFields {
  public:
    JsonFields(const nlohmann::json& object, std::string file, std::string path);

    // Rejects keys outside `allowed`, listing the allowed ones.
    void allow_only(std::initializer_list<const char*> allowed) const;
    bool has(const char* key) const { return object_.contains(key); }

    double number(const char* key, double fallback) const;
    double positive_number(const char* key, double fallback) const;
    double required_positive_number(const char* key) const;
    int integer(const char* key, int fallback, int min, int max) const;
    Vec3 vec3(const char* key, const Vec3& fallback) const;
    Vec3 positive_vec3(const char* key, const Vec3& fallback) const;
    std::string choice(const char* key, const std::string& fallback,
                       const std::vector<const char*>& allowed) const;
    // The setting at `key` as the enum whose values name in order (E(i) is names[i]).
    template <class E, std::size_t N>
    E choice(const char* key, E fallback, const std::array<const char*, N>& names) const {
        const std::string s = choice(key, names[std::size_t(fallback)],
                                     std::vector<const char*>(names.begin(), names.end()));
        std::size_t i = 0;
        while (s != names[i]) ++i;
        return E(i);
    }
    JsonFields object(const char* key) const;

    const nlohmann::json& at(const char* key) const { return object_.at(key); }
    std::string path_of(const std::string& key) const;
    [[noreturn]] void fail(const std::string& key, const std::string& expected) const;

  private:
    const nlohmann::json& object_;
    std::string file_, path_;
};

// Short description of a JSON value for messages: its type and a clipped dump.
std::string describe(const nlohmann::json& value);

}  // namespace hexmesh
