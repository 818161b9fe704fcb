/* JSON strings for summary.json and manifest.json. JSON text must be UTF-8, and the strings
 * we write carry what the user typed (an output directory, the options): control bytes
 * become \u00XX and a byte that does not belong to a well-formed UTF-8 sequence becomes
 * U+FFFD, so a path such as $'\x01\xff' still gives a file every JSON reader accepts. */
#include <spam/output.h>

/* Length of the well-formed UTF-8 sequence at s (RFC 3629: no overlongs, no surrogates,
 * nothing past U+10FFFF), or 0. */
static int Utf8Length(const unsigned char *s)
{
  int n;

  if (s[0] >= 0xc2 && s[0] <= 0xdf) n = 2;
  else if (s[0] >= 0xe0 && s[0] <= 0xef) n = 3;
  else if (s[0] >= 0xf0 && s[0] <= 0xf4) n = 4;
  else return 0;
  for (int k = 1; k < n; k++)
    if ((s[k] & 0xc0) != 0x80) return 0;
  if (s[0] == 0xe0 && s[1] < 0xa0) return 0; /* overlong */
  if (s[0] == 0xed && s[1] > 0x9f) return 0; /* surrogate */
  if (s[0] == 0xf0 && s[1] < 0x90) return 0; /* overlong */
  if (s[0] == 0xf4 && s[1] > 0x8f) return 0; /* past U+10FFFF */
  return n;
}

void SpamFileJsonString(SpamFile *f, const char *str)
{
  const unsigned char *c = (const unsigned char *)str;

  SpamFilePrintf(f, "\"");
  while (*c) {
    int n;
    if (*c == '"' || *c == '\\') SpamFilePrintf(f, "\\%c", *c++);
    else if (*c < 0x20 || *c == 0x7f) SpamFilePrintf(f, "\\u%04x", *c++);
    else if (*c < 0x80) SpamFilePrintf(f, "%c", *c++);
    else if ((n = Utf8Length(c)) > 0) {
      SpamFilePrintf(f, "%.*s", n, (const char *)c);
      c += n;
    } else {
      SpamFilePrintf(f, "\\ufffd");
      c++;
    }
  }
  SpamFilePrintf(f, "\"");
}
