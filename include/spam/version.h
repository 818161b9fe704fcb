#ifndef SPAM_VERSION_H
#define SPAM_VERSION_H
#define SPAM_VERSION "0.1.0"
#endif
