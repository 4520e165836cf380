# daisy_set_warnings(target): the house warning set (-Wall -Wextra -Wshadow), errors with DAISY_WERROR.
function(daisy_set_warnings target)
    target_compile_options(${target} PRIVATE -Wall -Wextra -Wshadow)
    if(DAISY_WERROR)
        target_compile_options(${target} PRIVATE -Werror)
    endif()
endfunction()
