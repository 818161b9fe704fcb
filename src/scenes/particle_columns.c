/* What a particle file gives against what the model can hold. A file's column the model
 * has no place for would be dropped without a word, and the run would not be the one the
 * file describes: that is bad input, named by column and by the model's state. */
#include <spam/scene.h>
#include <spam/errors.h>

PetscErrorCode SpamParticlesCheckColumns(const SpamParticles *p, const SpamLayout *l)
{
  static const struct {
    unsigned    bit;
    const char *column, *field;
  } fields[] = {
    {SPAM_COLUMN_E,      "e",                      "energy per unit mass e"},
    {SPAM_COLUMN_RHO,    "rho",                    "density rho (it sums the density from the positions)"},
    {SPAM_COLUMN_STRESS, "sxx, sxy, ... (stress)", "stress"},
  };
  char state[256];

  PetscFunctionBeginUser;
  PetscCall(SpamLayoutDescribe(l, state, sizeof state));
  for (size_t k = 0; k < sizeof fields / sizeof fields[0]; k++) {
    const int offset = fields[k].bit == SPAM_COLUMN_E ? l->e : fields[k].bit == SPAM_COLUMN_RHO ? l->rho : l->s;
    if ((p->columns & fields[k].bit) && offset < 0) SPAM_BAD_INPUT("column", fields[k].column, "the model (state: %s) has no %s; remove the column or choose a model that has it", state, fields[k].field);
  }
  PetscFunctionReturn(0);
}
