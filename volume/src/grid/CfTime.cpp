#include <atmoglobe/volume/CfTime.h>

#include <atmoglobe/globe/Text.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>

namespace atmoglobe::volume {

namespace {

bool gregorianLeap(std::int64_t y) { return (y % 4 == 0 && y % 100 != 0) || y % 400 == 0; }
bool julianLeap(std::int64_t y) { return y % 4 == 0; }

// Day number of 1 January of `year` (day 0 = 1 January of year 1) in each arithmetic calendar.
std::int64_t daysBeforeYear(CfCalendar c, std::int64_t year) {
  const std::int64_t y = year - 1;
  switch (c) {
    case CfCalendar::Standard:
    case CfCalendar::ProlepticGregorian: return 365 * y + y / 4 - y / 100 + y / 400;
    case CfCalendar::Julian: return 365 * y + y / 4;
    case CfCalendar::NoLeap: return 365 * y;
    case CfCalendar::AllLeap: return 366 * y;
    case CfCalendar::Day360: return 360 * y;
  }
  return 0;
}

int monthLength(CfCalendar c, std::int64_t year, int month) {
  static constexpr int kDays[12] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
  if (c == CfCalendar::Day360) return 30;
  if (month != 2) return kDays[month - 1];
  switch (c) {
    case CfCalendar::Standard:
    case CfCalendar::ProlepticGregorian: return gregorianLeap(year) ? 29 : 28;
    case CfCalendar::Julian: return julianLeap(year) ? 29 : 28;
    case CfCalendar::NoLeap: return 28;
    case CfCalendar::AllLeap: return 29;
    case CfCalendar::Day360: return 30;
  }
  return 28;
}

// The arithmetic part shared by every calendar: `c` here is never Standard's mixed form (the
// caller picks Julian or ProlepticGregorian for it).
std::int64_t arithmeticDayNumber(CfCalendar c, int year, int month, int day) {
  std::int64_t n = daysBeforeYear(c, year);
  for (int m = 1; m < month; ++m) n += monthLength(c, year, m);
  return n + (day - 1);
}

void arithmeticDate(CfCalendar c, std::int64_t n, int* year, int* month, int* day) {
  const double yearLength = c == CfCalendar::Day360    ? 360.0
                            : c == CfCalendar::NoLeap  ? 365.0
                            : c == CfCalendar::AllLeap ? 366.0
                            : c == CfCalendar::Julian  ? 365.25
                                                       : 365.2425;
  std::int64_t y = static_cast<std::int64_t>(std::floor(static_cast<double>(n) / yearLength)) + 1;
  while (daysBeforeYear(c, y) > n) --y;
  while (daysBeforeYear(c, y + 1) <= n) ++y;
  std::int64_t rest = n - daysBeforeYear(c, y);
  int m = 1;
  while (m < 12 && rest >= monthLength(c, y, m)) rest -= monthLength(c, y, m++);
  *year = static_cast<int>(y);
  *month = m;
  *day = static_cast<int>(rest) + 1;
}

// The standard (mixed) calendar counts days like the Julian one (day 0 = 0001-01-01 Julian,
// Julian day number 1721424); Gregorian dates from 1582-10-15 (Julian day number 2299161) on.
// Proleptic Gregorian day 0 (0001-01-01) is Julian day number 1721426: 2 days later.
constexpr std::int64_t kGregorianStartStandardDay = 2299161 - 1721424;
constexpr std::int64_t kGregorianToStandard = 2;

// Reads an unsigned decimal number at s[*i]; false if there is no digit.
bool readInt(const std::string& s, std::size_t* i, long long* out, std::size_t maxDigits = 9) {
  std::size_t j = *i;
  long long v = 0;
  while (j < s.size() && std::isdigit(static_cast<unsigned char>(s[j])) && j - *i < maxDigits)
    v = v * 10 + (s[j++] - '0');
  if (j == *i) return false;
  *i = j;
  *out = v;
  return true;
}

struct ParsedDateTime {
  int year = 0, month = 0, day = 0;
  long long secondsOfDay = 0;  // may be outside [0, 86400) after the zone offset
  double fraction = 0.0;
};

Result<ParsedDateTime> parseReference(const std::string& text) {
  const std::string s(trimAscii(text));
  auto bad = [&](const std::string& why) { return makeError("reference date '" + s + "': " + why); };
  ParsedDateTime p;
  std::size_t i = 0;
  long long y = 0, mo = 0, d = 0;
  if (!readInt(s, &i, &y, 4) || i >= s.size() || s[i] != '-') return bad("expected YYYY-MM-DD");
  ++i;
  if (!readInt(s, &i, &mo, 2) || i >= s.size() || s[i] != '-') return bad("expected YYYY-MM-DD");
  ++i;
  if (!readInt(s, &i, &d, 2)) return bad("expected YYYY-MM-DD");
  if (y < 1 || y > 9999) return bad("year outside 1..9999");
  if (mo < 1 || mo > 12 || d < 1 || d > 31) return bad("month or day out of range");
  p.year = static_cast<int>(y);
  p.month = static_cast<int>(mo);
  p.day = static_cast<int>(d);
  if (i < s.size() && (s[i] == 'T' || s[i] == 't')) ++i;
  while (i < s.size() && s[i] == ' ') ++i;
  long long h = 0, mi = 0, sec = 0;
  if (i < s.size() && std::isdigit(static_cast<unsigned char>(s[i]))) {
    if (!readInt(s, &i, &h, 2) || i >= s.size() || s[i] != ':') return bad("expected hh:mm after the date");
    ++i;
    if (!readInt(s, &i, &mi, 2)) return bad("expected hh:mm after the date");
    if (i < s.size() && s[i] == ':') {
      ++i;
      if (!readInt(s, &i, &sec, 2)) return bad("expected seconds after hh:mm:");
      if (i < s.size() && s[i] == '.') {
        ++i;
        double scale = 0.1;
        const std::size_t start = i;
        while (i < s.size() && std::isdigit(static_cast<unsigned char>(s[i]))) {
          p.fraction += scale * (s[i] - '0');
          scale *= 0.1;
          ++i;
        }
        if (i == start) return bad("expected digits after the decimal point");
      }
    }
    if (h > 24 || mi > 59 || sec > 60) return bad("time of day out of range");
  }
  p.secondsOfDay = h * 3600 + mi * 60 + sec;
  while (i < s.size() && s[i] == ' ') ++i;
  const std::string zone = toLowerAscii(std::string_view(s).substr(i));
  if (zone.empty() || zone == "z" || zone == "utc" || zone == "gmt") return p;
  // An offset: +hh, +hh:mm, +hhmm, -... (local time = UTC + offset).
  std::size_t k = 0;
  const std::string z = zone.rfind("utc", 0) == 0 ? zone.substr(3) : zone;
  if (z.empty() || (z[0] != '+' && z[0] != '-')) return bad("unknown time zone '" + zone + "'");
  const int sign = z[0] == '-' ? -1 : 1;
  k = 1;
  long long oh = 0, om = 0;
  const std::size_t before = k;
  if (!readInt(z, &k, &oh, 4)) return bad("unknown time zone '" + zone + "'");
  if (k - before == 4) {  // hhmm
    om = oh % 100;
    oh /= 100;
  } else if (k < z.size() && z[k] == ':') {
    ++k;
    if (!readInt(z, &k, &om, 2)) return bad("unknown time zone '" + zone + "'");
  }
  if (k != z.size() || oh > 14 || om > 59) return bad("unknown time zone '" + zone + "'");
  p.secondsOfDay -= sign * (oh * 3600 + om * 60);
  return p;
}

}  // namespace

const char* toString(CfCalendar c) {
  switch (c) {
    case CfCalendar::Standard: return "standard";
    case CfCalendar::ProlepticGregorian: return "proleptic_gregorian";
    case CfCalendar::Julian: return "julian";
    case CfCalendar::NoLeap: return "noleap";
    case CfCalendar::AllLeap: return "all_leap";
    case CfCalendar::Day360: return "360_day";
  }
  return "standard";
}

Result<CfCalendar> parseCfCalendar(const std::string& name) {
  const std::string n = toLowerAscii(trimAscii(name));
  if (n.empty() || n == "standard" || n == "gregorian") return CfCalendar::Standard;
  if (n == "proleptic_gregorian") return CfCalendar::ProlepticGregorian;
  if (n == "julian") return CfCalendar::Julian;
  if (n == "noleap" || n == "365_day" || n == "no_leap") return CfCalendar::NoLeap;
  if (n == "all_leap" || n == "366_day") return CfCalendar::AllLeap;
  if (n == "360_day") return CfCalendar::Day360;
  return makeError("calendar '" + name +
                   "' is not a CF calendar (standard, gregorian, proleptic_gregorian, "
                   "julian, noleap, 365_day, all_leap, 366_day, 360_day)");
}

bool cfDayNumber(CfCalendar c, int year, int month, int day, std::int64_t* dayNumber) {
  if (year < 1 || year > 9999 || month < 1 || month > 12 || day < 1) return false;
  if (c == CfCalendar::Standard) {
    const bool gregorian = year > 1582 || (year == 1582 && (month > 10 || (month == 10 && day >= 15)));
    const bool julian = year < 1582 || (year == 1582 && (month < 10 || (month == 10 && day <= 4)));
    if (!gregorian && !julian) return false;  // 1582-10-05 .. 1582-10-14 never happened
    const CfCalendar a = gregorian ? CfCalendar::ProlepticGregorian : CfCalendar::Julian;
    if (day > monthLength(a, year, month)) return false;
    *dayNumber = arithmeticDayNumber(a, year, month, day) + (gregorian ? kGregorianToStandard : 0);
    return true;
  }
  if (day > monthLength(c, year, month)) return false;
  *dayNumber = arithmeticDayNumber(c, year, month, day);
  return true;
}

void cfCalendarDate(CfCalendar c, std::int64_t n, int* year, int* month, int* day) {
  if (c == CfCalendar::Standard) {
    if (n >= kGregorianStartStandardDay)
      arithmeticDate(CfCalendar::ProlepticGregorian, n - kGregorianToStandard, year, month, day);
    else arithmeticDate(CfCalendar::Julian, n, year, month, day);
    return;
  }
  arithmeticDate(c, n, year, month, day);
}

Result<CfTimeUnits> parseCfTimeUnits(const std::string& units, const std::string& calendar) {
  auto cal = parseCfCalendar(calendar);
  if (!cal) return cal.forwardError();
  const std::string u(trimAscii(units));
  const std::string lu = toLowerAscii(u);
  const auto since = lu.find(" since ");
  if (since == std::string::npos)
    return makeError("time units '" + u + "' are not of the form 'UNIT since YYYY-MM-DD hh:mm:ss'");
  const std::string unit(trimAscii(std::string_view(lu).substr(0, since)));
  CfTimeUnits t;
  t.calendar = *cal;
  if (unit == "seconds" || unit == "second" || unit == "secs" || unit == "sec" || unit == "s") {
    t.secondsPerUnit = 1.0;
    t.unitName = "seconds";
  } else if (unit == "minutes" || unit == "minute" || unit == "mins" || unit == "min") {
    t.secondsPerUnit = 60.0;
    t.unitName = "minutes";
  } else if (unit == "hours" || unit == "hour" || unit == "hrs" || unit == "hr" || unit == "h") {
    t.secondsPerUnit = 3600.0;
    t.unitName = "hours";
  } else if (unit == "days" || unit == "day" || unit == "d") {
    t.secondsPerUnit = 86400.0;
    t.unitName = "days";
  } else if (unit == "months" || unit == "month" || unit == "years" || unit == "year" || unit == "common_years") {
    return makeError("time units '" + u + "': " + unit +
                     " have no fixed length (CF discourages them); only seconds, minutes, hours and days are read");
  } else {
    return makeError("time units '" + u + "': unknown unit '" + unit + "'");
  }
  auto ref = parseReference(u.substr(since + 7));
  if (!ref) return makeError("time units '" + u + "': " + ref.error());
  std::int64_t day = 0;
  if (!cfDayNumber(t.calendar, ref->year, ref->month, ref->day, &day))
    return makeError("time units '" + u + "': the date does not exist in the " + std::string(toString(t.calendar)) +
                     " calendar");
  t.referenceSeconds = day * 86400 + ref->secondsOfDay;
  t.referenceFractionSeconds = ref->fraction;
  t.referenceIso8601 = cfTimeToIso8601(t, 0.0);
  return t;
}

std::string cfTimeToIso8601(const CfTimeUnits& t, double value) {
  const double offset = value * t.secondsPerUnit + t.referenceFractionSeconds;
  // 1e12 s is ~31,700 years: beyond any date we can print; also keeps llround defined.
  if (!std::isfinite(offset) || std::fabs(offset) > 1e12) return {};
  const std::int64_t total = t.referenceSeconds + static_cast<std::int64_t>(std::llround(offset));
  const std::int64_t day = total >= 0 ? total / 86400 : -((-total + 86399) / 86400);
  const std::int64_t sod = total - day * 86400;
  if (day < 0) return {};
  int y = 0, m = 0, d = 0;
  cfCalendarDate(t.calendar, day, &y, &m, &d);
  if (y < 1 || y > 9999) return {};
  char buf[40];
  std::snprintf(buf, sizeof buf, "%04d-%02d-%02dT%02d:%02d:%02dZ", y, m, d, static_cast<int>(sod / 3600),
                static_cast<int>(sod / 60 % 60), static_cast<int>(sod % 60));
  return buf;
}

}  // namespace atmoglobe::volume
