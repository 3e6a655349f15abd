local n = 0
for i = 1, 20000 do
  local s = ""
  for j = 1, 20 do
    s = s .. string.char(65 + (i + j) % 26)
  end
  if string.sub(s, 5, 5) == "K" then n = n + 1 end
  n = n + #s
end
print(n)
