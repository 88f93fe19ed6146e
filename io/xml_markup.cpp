#include "io/xml_markup.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <optional>

#include "io/input_error.h"

namespace hexmesh::xml {
namespace {

// Elements nest this deep at most (a multiblock file of nested blocks needs a handful).
constexpr int kMostDepth = 64;

// Attributes an element may have (VTK writes at most a dozen): more is not a VTK file, and
// each new one is compared with all before it.
constexpr size_t kMostAttributes = 64;

class XmlParser {
  public:
    XmlParser(const std::string& path, std::string_view text) : path_(path), text_(text) {}

    Head parse() {
        Element document;
        std::vector<Element*> open{&document};
        size_t at = 0;
        std::optional<size_t> data_start;
        while (true) {
            const size_t lt = text_.find('<', at);
            const std::string_view between =
                text_.substr(at, lt == std::string_view::npos ? text_.npos : lt - at);
            if (std::any_of(between.begin(), between.end(),
                            [](char ch) { return !is_blank(ch); })) {
                if (open.size() == 1) fail_at(at, "text outside the <VTKFile> element");
                open.back()->text.append(between);
            }
            if (lt == std::string_view::npos) break;
            at = lt;
            if (starts(at, "<!--")) {
                at = skip_past(at, "-->", "a comment");
            } else if (starts(at, "<?")) {
                at = skip_past(at, "?>", "a processing instruction");
            } else if (starts(at, "<!")) {
                fail_at(at, "a <! declaration (DOCTYPE, CDATA), which VTK files do not hold");
            } else if (starts(at, "</")) {
                size_t p = at + 2;
                const std::string name = read_name(p);
                while (p < text_.size() && is_blank(text_[p])) ++p;
                if (p >= text_.size() || text_[p] != '>')
                    fail_at(at, fmt::format("</{}: expected '>'", name));
                if (open.size() == 1) fail_at(at, fmt::format("</{}> closes no element", name));
                if (open.back()->name != name)
                    fail_at(at, fmt::format("</{}> closes <{}>", name, open.back()->name));
                open.pop_back();
                at = p + 1;
            } else {
                Element element;
                bool closed = false;
                at = read_start_tag(at, element, closed);
                if (int(open.size()) > kMostDepth)
                    fail_at(lt, fmt::format("elements nested more than {} deep", kMostDepth));
                if (open.size() == 1 && !document.children.empty())
                    fail_at(lt, fmt::format("a second top element <{}>", element.name));
                Element* parent = open.back();
                parent->children.push_back(std::move(element));
                Element& added = parent->children.back();
                if (added.name == "AppendedData") {
                    if (closed) fail_at(lt, "an empty <AppendedData/> element");
                    // Its bytes start after the first '_' with nothing but blanks before it.
                    size_t p = at;
                    while (p < text_.size() && is_blank(text_[p])) ++p;
                    if (p >= text_.size() || text_[p] != '_')
                        fail("its AppendedData does not start with '_' after the tag");
                    data_start = p + 1;
                    break;
                }
                if (!closed) open.push_back(&added);
            }
        }
        if (!data_start && open.size() > 1)
            fail(fmt::format("the file ends inside <{}>", open.back()->name));
        if (document.children.empty() || document.children[0].name != "VTKFile")
            fail(document.children.empty()
                     ? "no <VTKFile> element (not a VTK XML file)"
                     : fmt::format("its top element is <{}>; expected <VTKFile>",
                                   document.children[0].name));
        Head head;
        head.root = std::move(document.children[0]);
        if (data_start) {
            if (head.root.children.empty() || head.root.children.back().name != "AppendedData")
                fail("its <AppendedData> is not an element of <VTKFile>");
            head.data_start = *data_start;
        }
        head.has_appended = bool(data_start);
        return head;
    }

  private:
    bool starts(size_t at, std::string_view what) const {
        return text_.compare(at, what.size(), what) == 0;
    }

    size_t skip_past(size_t at, std::string_view end, const char* what) const {
        const size_t found = text_.find(end, at);
        if (found == std::string_view::npos) fail_at(at, fmt::format("{} that does not end", what));
        return found + end.size();
    }

    static bool name_char(char ch) {
        return std::isalnum(static_cast<unsigned char>(ch)) || ch == '_' || ch == ':' ||
               ch == '.' || ch == '-';
    }

    std::string read_name(size_t& p) const {
        const size_t from = p;
        while (p < text_.size() && name_char(text_[p])) ++p;
        if (p == from) fail_at(from, "expected an element or attribute name");
        return std::string(text_.substr(from, p - from));
    }

    // "<name a="v" ...>" or ".../>" at `at`; returns the offset after it.
    size_t read_start_tag(size_t at, Element& element, bool& closed) const {
        size_t p = at + 1;
        element.name = read_name(p);
        while (true) {
            const size_t before = p;
            while (p < text_.size() && is_blank(text_[p])) ++p;
            if (p >= text_.size())
                fail_at(at, fmt::format("the file ends inside the tag <{}", element.name));
            if (text_[p] == '>') return p + 1;
            if (text_[p] == '/') {
                if (p + 1 >= text_.size() || text_[p + 1] != '>')
                    fail_at(p, fmt::format("<{}: expected '>' after '/'", element.name));
                closed = true;
                return p + 2;
            }
            if (p == before)
                fail_at(p, fmt::format("<{}: expected a blank before an attribute", element.name));
            std::string key = read_name(p);
            while (p < text_.size() && is_blank(text_[p])) ++p;
            if (p >= text_.size() || text_[p] != '=')
                fail_at(p, fmt::format("<{}: attribute {} without '='", element.name, key));
            ++p;
            while (p < text_.size() && is_blank(text_[p])) ++p;
            if (p >= text_.size() || (text_[p] != '"' && text_[p] != '\''))
                fail_at(p,
                        fmt::format("<{}: attribute {} without a quoted value", element.name, key));
            const size_t end = text_.find(text_[p], p + 1);
            if (end == std::string_view::npos)
                fail_at(p, fmt::format("<{}: attribute {} does not end", element.name, key));
            if (element.find(key))
                fail_at(p, fmt::format("<{}: attribute {} given twice", element.name, key));
            if (element.attributes.size() >= kMostAttributes)
                fail_at(p,
                        fmt::format("<{}: more than {} attributes", element.name, kMostAttributes));
            element.attributes.emplace_back(std::move(key),
                                            decode_entities(text_.substr(p + 1, end - p - 1), p));
            p = end + 1;
        }
    }

    std::string decode_entities(std::string_view raw, size_t at) const {
        std::string out;
        for (size_t k = 0; k < raw.size(); ++k) {
            if (raw[k] == '<') fail_at(at, "an attribute value holds '<'");
            if (raw[k] != '&') {
                out += raw[k];
                continue;
            }
            const size_t semi = raw.find(';', k);
            if (semi == std::string_view::npos)
                fail_at(at, "an '&' that starts no entity in an attribute value");
            const std::string_view name = raw.substr(k + 1, semi - k - 1);
            if (name == "lt")
                out += '<';
            else if (name == "gt")
                out += '>';
            else if (name == "amp")
                out += '&';
            else if (name == "quot")
                out += '"';
            else if (name == "apos")
                out += '\'';
            else if (name.size() > 1 && name[0] == '#') {
                const bool hex = name[1] == 'x';
                unsigned long code = 0;
                const std::string_view digits = name.substr(hex ? 2 : 1);
                const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(),
                                                       code, hex ? 16 : 10);
                if (ec != std::errc() || end != digits.data() + digits.size() || digits.empty() ||
                    code == 0 || code > 0x10FFFF)
                    fail_at(at, fmt::format("entity &{}; is not a character", printable(name)));
                append_utf8(out, code);
            } else {
                fail_at(at, fmt::format("unknown entity &{};", printable(name)));
            }
            k = semi;
        }
        return out;
    }

    static void append_utf8(std::string& out, unsigned long code) {
        if (code < 0x80) {
            out += char(code);
        } else if (code < 0x800) {
            out += char(0xC0 | (code >> 6));
            out += char(0x80 | (code & 0x3F));
        } else if (code < 0x10000) {
            out += char(0xE0 | (code >> 12));
            out += char(0x80 | ((code >> 6) & 0x3F));
            out += char(0x80 | (code & 0x3F));
        } else {
            out += char(0xF0 | (code >> 18));
            out += char(0x80 | ((code >> 12) & 0x3F));
            out += char(0x80 | ((code >> 6) & 0x3F));
            out += char(0x80 | (code & 0x3F));
        }
    }

    [[noreturn]] void fail(const std::string& why) const {
        throw InputError(fmt::format("{}: {}", path_, why));
    }
    [[noreturn]] void fail_at(size_t at, const std::string& why) const {
        const long line =
            1 +
            long(std::count(text_.begin(), text_.begin() + long(std::min(at, text_.size())), '\n'));
        throw InputError(fmt::format("{}:{}: {}", path_, line, why));
    }

    const std::string& path_;
    std::string_view text_;
};

}  // namespace

std::string printable(std::string_view text) {
    std::string out;
    for (size_t k = 0; k < text.size() && k < 40; ++k) {
        const auto ch = static_cast<unsigned char>(text[k]);
        if (ch >= 0x20 && ch < 0x7f)
            out += char(ch);
        else
            out += fmt::format("\\x{:02x}", ch);
    }
    if (text.size() > 40) out += "...";
    return out;
}

Head parse_head(const std::string& path, std::string_view text) {
    return XmlParser(path, text).parse();
}

}  // namespace hexmesh::xml
