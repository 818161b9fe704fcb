/* The model's settings (SpamModelSettings, as the model states them) as one JSON object,
 * stored with every snapshot (root attribute "model"), so that a snapshot says which
 * physics made it. */
#include <spam/output.h>

/* Appends to buf at *used, never past len (snprintf's count is clipped). */
static void Put(char *buf, size_t len, size_t *used, const char *fmt, ...) PETSC_ATTRIBUTE_FORMAT(4, 5);
static void Put(char *buf, size_t len, size_t *used, const char *fmt, ...)
{
  va_list ap;
  int     k;

  if (*used >= len) return;
  va_start(ap, fmt);
  k = vsnprintf(buf + *used, len - *used, fmt, ap);
  va_end(ap);
  if (k > 0) *used = PetscMin(len, *used + (size_t)k);
}

PetscErrorCode SpamModelSettingsJson(const SpamModel *m, char *buf, size_t len)
{
  SpamSetting set[SPAM_MAX_SETTINGS];
  const int   n    = SpamModelSettings(m, set);
  size_t      used = 0;

  PetscFunctionBeginUser;
  Put(buf, len, &used, "{\"dim\": %d, \"h\": %.17g", m->dim, m->kernel.h);
  for (int k = 0; k < n; k++) {
    if (set[k].str) Put(buf, len, &used, ", \"%s\": \"%s\"", set[k].key, set[k].str);
    else Put(buf, len, &used, ", \"%s\": %.17g", set[k].key, set[k].num);
  }
  Put(buf, len, &used, "}");
  PetscCheck(used < len, PETSC_COMM_SELF, PETSC_ERR_PLIB, "the model settings need more than %zu bytes", len);
  PetscFunctionReturn(0);
}
