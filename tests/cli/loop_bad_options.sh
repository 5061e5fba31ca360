# Nonsense options for jointhb loop: exit code 2 and one line naming the option.
source "$(dirname "$0")/common.inc" "$@"

check_names() {  # check_names OPTION ARGS...: bad input whose message names OPTION
  local option=$1; shift
  expect_bad_input loop "$@"
  grep -q -- "option '$option'" "$ERR" || fail "'$*': message does not name $option"
}

check_names --n --n 1.5
check_names --n --n 0
check_names --mu --mu -1
check_names --mu --mu=0
check_names --amplitude --amplitude nan
check_names --amplitude --amplitude=-inf
check_names --amplitude --amplitude -1e-6
check_names --law --law foo
check_names --normal-force --normal-force -5
check_names --kt0 --kt0 0
check_names --kt0 --kt0 inf
check_names --time-samples --time-samples 3
check_names --time-samples --time-samples 12.5
check_names --mu --mu abc
check_names --harmonic --harmonic 3
check_names --harmonic --harmonic 0,1e-6
check_names --harmonic --harmonic 3,-1e-6
check_names --harmonic --harmonic 200,1e-6
check_names --lambda --normal-amplitude 1e-6
check_names --lambda --lambda -1
check_names --csv --csv /nonexistent-jointhb-dir/loop.csv
grep -q 'nonexistent-jointhb-dir' "$ERR" || fail "--csv error does not name the path"
grep -q "must be > 0, got -1" <("$JOINTHB" loop --mu -1 2>&1) || fail "--mu -1 message wording"
finish
