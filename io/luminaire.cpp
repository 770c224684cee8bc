#include "luminaire.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <sstream>

#include "error.h"
#include "parse.h"
#include "text_file.h"

namespace retroprism {

namespace {

constexpr double kDeg = 3.14159265358979323846 / 180.0;
// Angles per axis and values per file: far beyond any goniometer's grid (0.1 degree steps over
// a sphere are 1801 x 3600), small enough that a corrupt count cannot exhaust memory.
constexpr int kMaxAngles = 2000;
constexpr double kMaxValues = 1e6;

std::string at(const std::string& name, int line) {
    return name + ":" + std::to_string(line);
}

// A number of a file with the line it is on.
struct Token {
    std::string text;
    int line = 0;
};

// The numbers of a file read one after the other, each error naming its line.
class TokenStream {
  public:
    TokenStream(std::vector<Token> tokens, std::string name, int lastLine)
        : tokens_(std::move(tokens)), name_(std::move(name)), lastLine_(lastLine) {}

    const Token& next(const std::string& what) {
        if (pos_ >= tokens_.size())
            throw InputError(at(name_, lastLine_) + ": the file ends before " + what);
        return tokens_[pos_++];
    }
    double number(const std::string& what, double lo, double hi) {
        const Token& t = next(what);
        const std::optional<double> v = try_parse_number(t.text);
        if (!v || *v < lo || *v > hi)
            throw InputError(at(name_, t.line) + ": " + what + " \"" + t.text +
                             "\"; expected a finite number in [" + number_text(lo) + ", " +
                             number_text(hi) + "]");
        return *v;
    }
    int count(const std::string& what, int lo, int hi) {
        const Token& t = next(what);
        const std::optional<double> v = try_parse_number(t.text);
        if (!v || *v != std::floor(*v) || *v < lo || *v > hi)
            throw InputError(at(name_, t.line) + ": " + what + " \"" + t.text +
                             "\"; expected a whole number in [" + std::to_string(lo) + ", " +
                             std::to_string(hi) + "]");
        return int(*v);
    }
    int line() const { return pos_ < tokens_.size() ? tokens_[pos_].line : lastLine_; }
    void expect_end(const std::string& what) const {
        if (pos_ < tokens_.size())
            throw InputError(at(name_, tokens_[pos_].line) + ": \"" + tokens_[pos_].text +
                             "\" after " + what + "; expected the end of the file");
    }

  private:
    std::vector<Token> tokens_;
    std::string name_;
    int lastLine_;
    size_t pos_ = 0;
};

// The fields of `line` separated by blanks or commas.
void split_numbers(const std::string& line, int lineNo, std::vector<Token>& out) {
    std::string field;
    for (size_t i = 0; i <= line.size(); ++i) {
        const char c = i < line.size() ? line[i] : ' ';
        if (c == ' ' || c == '\t' || c == ',' || c == '\r' || c == '\n') {
            if (!field.empty()) out.push_back({field, lineNo});
            field.clear();
        } else {
            field += c;
        }
    }
}

// `n` angles in [lo, hi], strictly ascending.
std::vector<double> read_angles(TokenStream& ts, int n, const std::string& what, double lo,
                                double hi, const std::string& name) {
    std::vector<double> a;
    for (int k = 0; k < n; ++k) {
        const int line = ts.line();
        a.push_back(ts.number(what + " " + std::to_string(k + 1), lo, hi));
        if (k > 0 && !(a[k] > a[k - 1]))
            throw InputError(at(name, line) + ": " + what + " " + std::to_string(k + 1) + " (" +
                             number_text(a[k]) + ") does not exceed the one before it (" +
                             number_text(a[k - 1]) + "); expected strictly ascending angles");
    }
    return a;
}

// The horizontal angles' symmetry rule (luminaire.h) for the type; `line` where they start.
void check_horizontal(const LuminousIntensityDistribution& d, const std::string& at) {
    const std::vector<double>& h = d.horizontal_deg;
    if (d.type == PhotometricType::C) {
        if (h.front() != 0)
            throw InputError(at + ": the first horizontal (C) angle is " + number_text(h.front()) +
                             "; expected 0 for photometric type C");
        const double last = h.back();
        if (!(last == 0 || last == 90 || last == 180 || (last > 180 && last <= 360)))
            throw InputError(at + ": the last horizontal (C) angle is " + number_text(last) +
                             "; expected 0, 90, 180 or above 180 up to 360 (LM-63 symmetry)");
    }
}

// The value at `x` of the ascending grid `a`: the index i and weight t with x between a[i]
// and a[i + 1]; false when x is outside [a.front(), a.back()].
bool locate(const std::vector<double>& a, double x, size_t& i, double& t) {
    if (a.size() == 1) {
        i = 0;
        t = 0;
        return x == a[0];
    }
    if (!(x >= a.front() && x <= a.back())) return false;
    i = size_t(std::upper_bound(a.begin(), a.end(), x) - a.begin());
    i = std::min(std::max<size_t>(i, 1), a.size() - 1) - 1;
    t = (x - a[i]) / (a[i + 1] - a[i]);
    return true;
}

} // namespace

const char* photometric_type_name(PhotometricType t) {
    return t == PhotometricType::A ? "A" : t == PhotometricType::B ? "B" : "C";
}

glm::dvec2 photometric_angles(PhotometricType t, const glm::dvec3& d) {
    if (t == PhotometricType::A)
        return {std::atan2(d.x, d.z) / kDeg, std::atan2(d.y, std::hypot(d.x, d.z)) / kDeg};
    if (t == PhotometricType::B)
        return {std::atan2(d.x, std::hypot(d.y, d.z)) / kDeg, std::atan2(d.y, d.z) / kDeg};
    double c = std::atan2(-d.x, d.z) / kDeg;
    if (c < 0) c += 360;
    return {c >= 360 ? 0.0 : c, std::atan2(std::hypot(d.x, d.z), -d.y) / kDeg};
}

double LuminousIntensityDistribution::intensity(const glm::dvec3& direction) const {
    if (!std::isfinite(direction.x) || !std::isfinite(direction.y) || !std::isfinite(direction.z) ||
        glm::dot(direction, direction) == 0)
        return 0;
    const glm::dvec2 hv = photometric_angles(type, direction);
    return intensity_at(hv.x, hv.y);
}

double LuminousIntensityDistribution::intensity_at(double h, double v) const {
    size_t iv = 0, ih = 0;
    double tv = 0, th = 0;
    if (horizontal_deg.empty() || !std::isfinite(h) || !locate(vertical_deg, v, iv, tv)) return 0;
    const size_t nv = vertical_deg.size();
    auto at_col = [&](size_t col) {
        const double a = candela[col * nv + iv];
        return tv == 0 ? a : a + (candela[col * nv + iv + 1] - a) * tv;
    };
    if (horizontal_deg.size() == 1) return at_col(0);
    const double last = horizontal_deg.back();
    if (type == PhotometricType::C) {
        h = std::fmod(h, 360.0);
        if (h < 0) h += 360;
        if (last == 0) return at_col(0);
        if (last == 90) h = h <= 90 ? h : h <= 180 ? 180 - h : h <= 270 ? h - 180 : 360 - h;
        if (last == 180 && h > 180) h = 360 - h;
        if (h > last) { // between the last plane and 360, toward C 0
            const double w = (h - last) / (360 - last);
            return at_col(horizontal_deg.size() - 1) * (1 - w) + at_col(0) * w;
        }
    } else if (horizontal_deg.front() == 0) {
        h = std::abs(h);
    }
    if (!locate(horizontal_deg, h, ih, th)) return 0;
    return th == 0 ? at_col(ih) : at_col(ih) * (1 - th) + at_col(ih + 1) * th;
}

// ---------------------------------------------------------------------------------------------
// IES LM-63

namespace {

// The header line and keyword lines up to TILT=NONE; returns the line number of TILT.
int read_ies_header(const std::vector<std::string>& lines, const std::string& name) {
    const char* const kHeaders =
        "a first line IESNA:LM-63-2002, IES:LM-63-2019, IESNA:LM-63-1995 or IESNA91, or "
        "(LM-63-1986) a keyword line [KEYWORD] or TILT=NONE";
    for (size_t i = 0; i < lines.size(); ++i) {
        const std::string line = trim(lines[i]);
        const std::string where = at(name, int(i) + 1);
        if (line.rfind("TILT=", 0) == 0 || line.rfind("TILT =", 0) == 0) {
            const std::string value = trim(line.substr(line.find('=') + 1));
            if (value != "NONE")
                throw InputError(where + ": TILT=" + value +
                                 " is not read; expected TILT=NONE (a headlamp's distribution "
                                 "measured in its mounting position)");
            return int(i) + 1;
        }
        if (i == 0 && (line.rfind("IESNA", 0) == 0 || line.rfind("IES:LM-63", 0) == 0)) continue;
        if (i == 0 && line.rfind("[", 0) != 0)
            throw InputError(where + ": \"" + line.substr(0, 40) + "\"; expected " + kHeaders);
        if (!line.empty() && line[0] != '[')
            throw InputError(where + ": \"" + line.substr(0, 40) +
                             "\" before the TILT line; expected a keyword line [KEYWORD] ... or "
                             "TILT=NONE");
    }
    throw InputError(at(name, std::max<int>(1, int(lines.size()))) +
                     ": the file ends before its TILT line; expected TILT=NONE after the "
                     "keyword lines");
}

std::vector<std::string> split_lines(std::istream& in) {
    std::vector<std::string> lines;
    std::string raw;
    while (std::getline(in, raw)) {
        if (lines.empty() && raw.compare(0, 3, "\xEF\xBB\xBF") == 0) raw.erase(0, 3); // UTF-8 BOM
        if (!raw.empty() && raw.back() == '\r') raw.pop_back();
        lines.push_back(raw);
    }
    return lines;
}

// The candela values: `planes` planes of `nv` values each, every one finite and >= 0.
std::vector<double> read_candela(TokenStream& ts, size_t planes, size_t nv,
                                 const std::string& unit) {
    std::vector<double> c(planes * nv);
    for (size_t p = 0; p < planes; ++p)
        for (size_t v = 0; v < nv; ++v)
            c[p * nv + v] = ts.number("value " + std::to_string(v + 1) +
                                          (planes > 1 ? " of plane " + std::to_string(p + 1) : "") +
                                          " (" + unit + ")",
                                      0, 1e12);
    return c;
}

} // namespace

LuminousIntensityDistribution parse_ies(std::istream& in, const std::string& name) {
    const std::vector<std::string> lines = split_lines(in);
    const int tiltLine = read_ies_header(lines, name);
    std::vector<Token> tokens;
    for (size_t i = size_t(tiltLine); i < lines.size(); ++i)
        split_numbers(lines[i], int(i) + 1, tokens);
    TokenStream ts(std::move(tokens), name, std::max<int>(1, int(lines.size())));
    LuminousIntensityDistribution d;
    d.file = name;
    ts.count("the number of lamps", 1, 1000);
    ts.number("the lumens per lamp (-1: absolute photometry)", -1, 1e9);
    const double candelaMultiplier = ts.number("the candela multiplier", 0, 1e9);
    const int nv = ts.count("the number of vertical angles", 1, kMaxAngles);
    const int nh = ts.count("the number of horizontal angles", 1, kMaxAngles);
    if (double(nv) * nh > kMaxValues)
        throw InputError(at(name, ts.line()) + ": " + std::to_string(nv) + " x " +
                         std::to_string(nh) + " candela values; expected at most " +
                         number_text(kMaxValues));
    const int type = ts.count("the photometric type (1: C, 2: B, 3: A)", 1, 3);
    d.type = type == 1 ? PhotometricType::C : type == 2 ? PhotometricType::B : PhotometricType::A;
    ts.count("the units type (1: feet, 2: metres)", 1, 2);
    for (const char* dim : {"width", "length", "height"})
        ts.number(std::string("the luminous opening's ") + dim, -1e6, 1e6);
    const double ballast = ts.number("the ballast factor", 0, 1e3);
    ts.number("the ballast-lamp factor or file generation type", -1e9, 1e9);
    ts.number("the input watts", -1e9, 1e9);
    const bool typeC = d.type == PhotometricType::C;
    d.vertical_deg = read_angles(ts, nv, "vertical angle", typeC ? 0 : -90, typeC ? 180 : 90, name);
    const int hLine = ts.line();
    d.horizontal_deg =
        read_angles(ts, nh, "horizontal angle", typeC ? 0 : -180, typeC ? 360 : 180, name);
    check_horizontal(d, at(name, hLine));
    d.multiplier = candelaMultiplier * ballast;
    d.candela = read_candela(ts, size_t(nh), size_t(nv), "cd");
    for (double& c : d.candela)
        c *= d.multiplier;
    ts.expect_end("the last candela value");
    return d;
}

// ---------------------------------------------------------------------------------------------
// EULUMDAT

namespace {

// The C plane stored for plane angle `c` under symmetry `isym` (EULUMDAT: 1 about the vertical
// axis, 2 about C 0-180, 3 about C 90-270, 4 about both).
double stored_plane(int isym, double c) {
    switch (isym) {
    case 2:
        return c <= 180 ? c : 360 - c;
    case 3:
        return c >= 90 && c <= 270 ? c : c < 90 ? 180 - c : 540 - c;
    case 4:
        return c <= 90 ? c : c <= 180 ? 180 - c : c <= 270 ? c - 180 : 360 - c;
    default:
        return c;
    }
}

bool stored(int isym, double c) {
    return isym == 0 || (isym == 2 && c <= 180) || (isym == 3 && c >= 90 && c <= 270) ||
           (isym == 4 && c <= 90);
}

// Every listed C plane from the stored ones; InputError when a plane's mirror is not listed.
std::vector<double> expand_planes(const std::vector<double>& cAngles, int isym,
                                  const std::vector<double>& storedValues, size_t ng,
                                  const std::string& where) {
    std::vector<double> storedAngles;
    for (double c : cAngles)
        if (stored(isym, c)) storedAngles.push_back(c);
    std::vector<double> out;
    for (double c : cAngles) {
        const double m = stored_plane(isym, c);
        const auto it = std::find_if(storedAngles.begin(), storedAngles.end(),
                                     [&](double s) { return std::abs(s - m) < 1e-6; });
        if (it == storedAngles.end())
            throw InputError(where + ": the C plane " + number_text(c) + " has no mirror plane " +
                             number_text(m) +
                             " among the listed C angles; expected C angles symmetric under "
                             "the symmetry indicator");
        const size_t k = size_t(it - storedAngles.begin());
        out.insert(out.end(), storedValues.begin() + long(k * ng),
                   storedValues.begin() + long((k + 1) * ng));
    }
    return out;
}

size_t stored_count(const std::vector<double>& cAngles, int isym) {
    if (isym == 1) return 1;
    return size_t(
        std::count_if(cAngles.begin(), cAngles.end(), [&](double c) { return stored(isym, c); }));
}

// Lines 1 to 26f and the direct ratios; returns {isym, mc, ng, flux}.
struct LdtHeader {
    int isym = 0, mc = 0, ng = 0;
    double flux = 0;
};

LdtHeader read_ldt_header(TokenStream& ts) {
    LdtHeader h;
    ts.count("the type indicator Ityp (line 2)", 0, 3);
    h.isym = ts.count("the symmetry indicator Isym (line 3)", 0, 4);
    h.mc = ts.count("the number of C planes Mc (line 4)", 1, kMaxAngles);
    ts.number("the C plane spacing Dc (line 5)", 0, 360);
    h.ng = ts.count("the number of intensities per C plane Ng (line 6)", 1, kMaxAngles);
    ts.number("the intensity spacing Dg (line 7)", 0, 180);
    for (int k = 13; k <= 25; ++k)
        ts.number("line " + std::to_string(k) + " (dimensions, ratios, factors)", -1e9, 1e9);
    const int sets = ts.count("the number of lamp sets (line 26)", 1, 20);
    for (int s = 0; s < sets; ++s) {
        ts.next("the number of lamps of set " + std::to_string(s + 1));
        ts.next("the lamp type of set " + std::to_string(s + 1));
        h.flux += ts.number("the luminous flux of lamp set " + std::to_string(s + 1) + " in lm",
                            1e-6, 1e9);
        ts.next("the colour temperature of set " + std::to_string(s + 1));
        ts.next("the colour rendering index of set " + std::to_string(s + 1));
        ts.next("the wattage of set " + std::to_string(s + 1));
    }
    for (int k = 1; k <= 10; ++k)
        ts.number("direct ratio " + std::to_string(k) + " (line 27)", -1e9, 1e9);
    return h;
}

} // namespace

LuminousIntensityDistribution parse_eulumdat(std::istream& in, const std::string& name) {
    const std::vector<std::string> lines = split_lines(in);
    // Each field on its own line; free text (lines 1, 8-12 and the lamps' type, colour
    // temperature, colour rendering and wattage) is taken whole.
    const int lastLine = std::max<int>(1, int(lines.size()));
    std::vector<Token> tokens;
    for (size_t i = 0; i < lines.size(); ++i)
        if (i > 0 && !(i >= 7 && i <= 11)) tokens.push_back({trim(lines[i]), int(i) + 1});
    while (!tokens.empty() && tokens.back().text.empty())
        tokens.pop_back();
    if (lines.empty()) throw InputError(at(name, 1) + ": an empty file; expected EULUMDAT lines");
    TokenStream ts(std::move(tokens), name, lastLine);
    const LdtHeader h = read_ldt_header(ts);
    if (double(h.mc) * h.ng > kMaxValues)
        throw InputError(at(name, 6) + ": " + std::to_string(h.mc) + " x " + std::to_string(h.ng) +
                         " intensities; expected at most " + number_text(kMaxValues));
    LuminousIntensityDistribution d;
    d.file = name;
    d.type = PhotometricType::C;
    if ((h.isym == 2 || h.isym == 3) && h.mc % 2 != 0)
        throw InputError(at(name, 4) + ": Mc " + std::to_string(h.mc) +
                         " is odd; expected an even number of C planes for symmetry indicator " +
                         std::to_string(h.isym));
    if (h.isym == 4 && h.mc % 4 != 0)
        throw InputError(at(name, 4) + ": Mc " + std::to_string(h.mc) +
                         " is not a multiple of 4; expected one for symmetry indicator 4");
    const int cLine = ts.line();
    const std::vector<double> c = read_angles(ts, h.mc, "C angle", 0, 360, name);
    if (c.front() != 0 || c.back() >= 360)
        throw InputError(at(name, cLine) + ": C angles from " + number_text(c.front()) + " to " +
                         number_text(c.back()) +
                         "; expected them from 0 to below 360 (C 360 is "
                         "C 0)");
    d.vertical_deg = read_angles(ts, h.ng, "gamma angle", 0, 180, name);
    const size_t planes = stored_count(c, h.isym);
    const std::vector<double> values = read_candela(ts, planes, size_t(h.ng), "cd/klm");
    ts.expect_end("the last intensity");
    d.multiplier = h.flux / 1000;
    if (h.isym == 1) {
        d.horizontal_deg = {0};
        d.candela = values;
    } else {
        d.horizontal_deg = c;
        d.candela = expand_planes(c, h.isym, values, size_t(h.ng), at(name, cLine));
    }
    for (double& v : d.candela)
        v *= d.multiplier;
    return d;
}

// ---------------------------------------------------------------------------------------------
// CSV

namespace {

// The header row: the type and the horizontal angles.
void read_csv_header(const std::vector<std::string>& f, LuminousIntensityDistribution& d,
                     const std::string& name, int lineNo) {
    const std::string where = at(name, lineNo);
    if (f[0] != "A" && f[0] != "B" && f[0] != "C")
        throw InputError(where + ", column 1: \"" + f[0] +
                         "\"; expected the photometric type A, B or C, then the horizontal "
                         "angles");
    d.type = f[0] == "A"   ? PhotometricType::A
             : f[0] == "B" ? PhotometricType::B
                           : PhotometricType::C;
    if (f.size() < 2 || f.size() > size_t(kMaxAngles) + 1)
        throw InputError(where + ": " + std::to_string(f.size() - 1) +
                         " horizontal angles; expected 1 to " + std::to_string(kMaxAngles));
    std::vector<Token> tokens;
    for (size_t k = 1; k < f.size(); ++k)
        tokens.push_back({f[k], lineNo});
    const bool typeC = d.type == PhotometricType::C;
    TokenStream ts(std::move(tokens), name, lineNo);
    d.horizontal_deg = read_angles(ts, int(f.size()) - 1, "horizontal angle", typeC ? 0 : -180,
                                   typeC ? 360 : 180, name);
    check_horizontal(d, where);
}

} // namespace

LuminousIntensityDistribution parse_candela_csv(std::istream& in, const std::string& name) {
    const std::vector<std::string> lines = split_lines(in);
    LuminousIntensityDistribution d;
    d.file = name;
    for (size_t i = 0; i < lines.size(); ++i) {
        const std::string line = trim(lines[i]);
        const std::string where = at(name, int(i) + 1);
        if (line.empty() || line[0] == '#') continue;
        const std::vector<std::string> f = split_csv(line);
        if (d.horizontal_deg.empty()) {
            read_csv_header(f, d, name, int(i) + 1);
            continue;
        }
        if (f.size() != d.horizontal_deg.size() + 1)
            throw InputError(where + ": " + std::to_string(f.size()) + " fields; expected " +
                             std::to_string(d.horizontal_deg.size() + 1) +
                             " (a vertical angle, then one intensity per horizontal angle)");
        if (d.vertical_deg.size() >= size_t(kMaxAngles) ||
            double(d.vertical_deg.size() + 1) * double(d.horizontal_deg.size()) > kMaxValues)
            throw InputError(
                where + ": more than " +
                std::to_string(std::min<size_t>(size_t(kMaxAngles),
                                                size_t(kMaxValues) / d.horizontal_deg.size())) +
                " rows; expected at most 2000 vertical angles and 1e+06 values");
        std::vector<Token> tokens;
        for (const std::string& s : f)
            tokens.push_back({s, int(i) + 1});
        TokenStream ts(std::move(tokens), name, int(i) + 1);
        const bool typeC = d.type == PhotometricType::C;
        const double v = ts.number("the vertical angle", typeC ? 0 : -90, typeC ? 180 : 90);
        if (!d.vertical_deg.empty() && !(v > d.vertical_deg.back()))
            throw InputError(where + ": the vertical angle " + number_text(v) +
                             " does not exceed the row before it (" +
                             number_text(d.vertical_deg.back()) +
                             "); expected rows by ascending vertical angle");
        d.vertical_deg.push_back(v);
        d.candela.resize(d.candela.size() + d.horizontal_deg.size());
        const std::vector<double> row = read_candela(ts, 1, d.horizontal_deg.size(), "cd");
        std::copy(row.begin(), row.end(), d.candela.end() - long(row.size()));
    }
    if (d.vertical_deg.empty())
        throw InputError(at(name, std::max<int>(1, int(lines.size()))) +
                         (d.horizontal_deg.empty()
                              ? ": no header row; expected a row TYPE, H1, H2, ... and one row "
                                "per vertical angle"
                              : ": no rows; expected one row per vertical angle after the "
                                "header row"));
    // Rows were read by vertical angle; the grid is stored by horizontal plane.
    const size_t nh = d.horizontal_deg.size(), nv = d.vertical_deg.size();
    std::vector<double> byPlane(nh * nv);
    for (size_t v = 0; v < nv; ++v)
        for (size_t h = 0; h < nh; ++h)
            byPlane[h * nv + v] = d.candela[v * nh + h];
    d.candela = std::move(byPlane);
    return d;
}

LuminousIntensityDistribution read_luminaire(const std::string& path) {
    std::string ext = path.substr(std::min(path.size(), path.rfind('.') + 1));
    if (path.rfind('.') == std::string::npos) ext.clear();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    if (ext != "ies" && ext != "ldt" && ext != "csv")
        throw InputError(path + ": unknown luminaire file type \"." + ext +
                         "\"; expected .ies (IES LM-63), .ldt (EULUMDAT) or .csv (candela matrix)");
    std::istringstream in(read_text_file(path));
    return ext == "ies"   ? parse_ies(in, path)
           : ext == "ldt" ? parse_eulumdat(in, path)
                          : parse_candela_csv(in, path);
}

std::pair<LuminousIntensityDistribution, LuminousIntensityDistribution>
read_headlamp_pair(const std::string& files) {
    std::vector<std::string> names;
    std::istringstream ss(files);
    std::string item;
    while (std::getline(ss, item, ','))
        names.push_back(trim(item));
    if (names.empty() || names.size() > 2 || names.front().empty() || names.back().empty())
        throw InputError("--headlamps " + files +
                         ": expected FILE (both lamps) or LEFT,RIGHT (.ies, .ldt or .csv)");
    LuminousIntensityDistribution left = read_luminaire(names.front());
    return {left, names.size() == 1 ? left : read_luminaire(names.back())};
}

} // namespace retroprism
