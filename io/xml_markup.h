// Private to io/: the XML of a VTK XML file up to its appended data, parsed by a reader of
// our own that bounds what a hostile file can ask for (nesting, attributes), and quoting of
// untrusted text in messages.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace hexmesh::xml {

inline bool is_blank(char ch) {
    return ch == ' ' || ch == '\t' || ch == '\r' || ch == '\n';
}

// `text` as a message quotes it: at most 40 characters, bytes outside printable ASCII as \xNN.
std::string printable(std::string_view text);

// One element of the file's XML: its name, attributes (entities decoded) and text (inline data).
struct Element {
    std::string name;
    std::vector<std::pair<std::string, std::string>> attributes;
    std::string text;
    std::vector<Element> children;

    const std::string* find(std::string_view key) const {
        for (const auto& [k, v] : attributes)
            if (k == key) return &v;
        return nullptr;
    }
    std::string value(std::string_view key, const std::string& fallback = "") const {
        const std::string* v = find(key);
        return v ? *v : fallback;
    }
    const Element* child(std::string_view child_name) const {
        for (const Element& c : children)
            if (c.name == child_name) return &c;
        return nullptr;
    }
};

// The file's XML up to its appended data: the <VTKFile> element, and where the appended bytes
// start (after the '_' that follows <AppendedData ...>), if the file has them.
struct Head {
    Element root;
    bool has_appended = false;  // root's last child is its <AppendedData>
    size_t data_start = 0;      // file offset of the first appended byte
    const Element& appended() const { return root.children.back(); }
};

// Parses `text`, the start of the file `path`, up to the first byte of its appended data (the
// '_' after <AppendedData ...>) or its end: one <VTKFile> element (comments and <?...?> skipped;
// entities in attribute values decoded). Throws InputError naming the file, the line and the
// fault: a tag that does not close or closes another, text outside <VTKFile>, a DOCTYPE or
// CDATA, an unknown entity, elements nested more than 64 deep, more than 64 attributes on one.
Head parse_head(const std::string& path, std::string_view text);

}  // namespace hexmesh::xml
